//! polygon_interpolator against its f64 twin.
//!
//! Error bound (derived from the widths; also in docs/units.md#polygon_interpolator).
//! Let f = acc_frac_bits. Setup produces the start value S (at the bounding box's first
//! pixel centre (x0, y0)) and the gradients Gx, Gy each by ONE rounding-to-nearest
//! division of the exact rational, so each is within 2^-(f+1) of the exact value (in
//! attribute units). The walker only adds: at pixel (x, y) the accumulator holds
//! S + (x−x0)·Gx + (y−y0)·Gy (modulo 2^W under WRAP, which is harmless while the true
//! value fits), and the serpentine walk keeps x ≥ x0, y ≥ y0, so
//!     |acc − A(x, y)| ≤ (1 + (x−x0) + (y−y0)) · 2^-(f+1)  ≤  (k + 1) · 2^-(f+1),
//! k = moves made since the first pixel (the Manhattan distance never exceeds k).
//! Output rounding adds 0 when out_frac ≥ f (an exact shift), else ≤ ½ output LSB for the
//! round-to-nearest modes (< 1 LSB for TRN / TRN_ZERO). Output saturation is a clamp,
//! which is 1-Lipschitz, so the output is compared against clamp(twin, output range).
//! The twin evaluates the plane from the same quantised vertices, so nothing else
//! differs; 1e-9 covers the twin's own f64 rounding.
//!
//! Coverage: the unit's edge functions are exact integers on the half-sub-pixel grid and
//! the twin's f64 edge functions are exact for these coordinates, so the inside flags
//! must be EQUAL everywhere (top-left rule in both).

mod common;

use glare_pipeline::reference::polygon_interpolator as twin;
use proptest::prelude::*;
use rtl_model::driver::run_span;
use rtl_model::units::polygon_interpolator::{
    Barycentric, Move, PolyLanes, PolyOut, PolySetup, PolyState, PolygonInterpolator,
    PolygonInterpolatorConfig, Vertex, MAX_ATTRS,
};
use rtl_model::{Counters, Format, Overflow, Quant, Unit, UnitSummary};

const SLACK: f64 = 1e-9;

fn s_fmt(i: u32, f: u32) -> Format {
    Format {
        int_bits: i,
        frac_bits: f,
        signed: true,
    }
}

/// A vertex from raw words: position in sub-pixel codes, the given attribute codes
/// first and 0 after them.
fn raw_vertex(x: i64, y: i64, attrs: &[i64]) -> Vertex {
    let mut a = [0i64; MAX_ATTRS];
    a[..attrs.len()].copy_from_slice(attrs);
    Vertex { x, y, attrs: a }
}

/// Default widths with K attributes.
fn cfg_default(k: u32) -> PolygonInterpolator {
    PolygonInterpolatorConfig {
        attrs: k,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap()
}

/// Wide: 32 accumulator fraction bits, 16 output fraction bits.
fn cfg_wide(k: u32) -> PolygonInterpolator {
    PolygonInterpolatorConfig {
        attrs: k,
        acc_int_bits: 24,
        acc_frac_bits: 32,
        out_int_bits: 16,
        out_frac_bits: 16,
        out_quant: Quant::RndConv,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap()
}

/// Narrow: 3 accumulator fraction bits, 4 output fraction bits (large error).
fn cfg_narrow(k: u32) -> PolygonInterpolator {
    PolygonInterpolatorConfig {
        attrs: k,
        subpixel_bits: 2,
        acc_int_bits: 12,
        acc_frac_bits: 3,
        out_int_bits: 9,
        out_frac_bits: 4,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap()
}

fn config_by_index(i: usize, k: u32) -> PolygonInterpolator {
    match i {
        0 => cfg_default(k),
        1 => cfg_wide(k),
        _ => cfg_narrow(k),
    }
}

/// Output rounding bound in attribute units.
fn out_round_bound(u: &PolygonInterpolator) -> f64 {
    let (f, o) = (u.acc_frac_bits(), u.out_frac_bits());
    if o >= f {
        0.0
    } else {
        match u.out_quant() {
            Quant::Trn | Quant::TrnZero => (-(o as f64)).exp2(),
            _ => (-(o as f64 + 1.0)).exp2(),
        }
    }
}

/// The derived bound at Manhattan distance `dist` from the first pixel.
fn bound(u: &PolygonInterpolator, dist: u64) -> f64 {
    (1 + dist) as f64 * (-(u.acc_frac_bits() as f64 + 1.0)).exp2() + out_round_bound(u)
}

fn clamp_out(u: &PolygonInterpolator, v: f64) -> f64 {
    let of = u.out_fmt();
    v.clamp(
        u.out_to_f64(of.min_raw() as i64),
        u.out_to_f64(of.max_raw() as i64),
    )
}

/// Walk a set-up primitive and compare with the twin: coverage must be equal at every
/// bounding-box pixel; covered pixels' attributes must lie within the bound. Returns the
/// covered pixels, the outputs and the largest error seen as a fraction of its bound.
fn check_walk(
    u: &PolygonInterpolator,
    setup: &PolySetup,
    covers: &dyn Fn(i64, i64) -> bool,
    value: &dyn Fn(usize, i64, i64) -> f64,
) -> (Vec<(i64, i64)>, Vec<PolyOut>) {
    let moves = setup.moves();
    let mut st = setup.state.clone();
    let mut ctr = Counters::default();
    let outs = run_span(u, &mut st, &moves, &mut ctr);
    assert_eq!(outs.len() as u64, setup.pixels());
    let mut covered = Vec::new();
    let b = setup.bbox;
    for (k, o) in outs.iter().enumerate() {
        let b = b.unwrap();
        assert!(o.x >= b.x0 && o.x <= b.x1 && o.y >= b.y0 && o.y <= b.y1);
        let want = covers(o.x, o.y);
        assert_eq!(o.inside, want, "coverage differs at ({}, {})", o.x, o.y);
        if !o.inside {
            continue;
        }
        covered.push((o.x, o.y));
        let dist = ((o.x - b.x0) + (o.y - b.y0)) as u64;
        assert!(
            dist <= k as u64,
            "Manhattan distance exceeds the move count"
        );
        for i in 0..u.attrs() as usize {
            let got = u.out_to_f64(o.attrs[i]);
            let want = clamp_out(u, value(i, o.x, o.y));
            let bd = bound(u, dist);
            assert!(
                (got - want).abs() <= bd + SLACK,
                "attr {i} at ({}, {}): got {got}, twin {want}, err {}, bound {bd} (dist {dist})",
                o.x,
                o.y,
                (got - want).abs()
            );
        }
    }
    (covered, outs)
}

/// Every pixel the twin covers within `window` must lie in the bounding box.
fn check_bbox_holds_coverage(
    setup: &PolySetup,
    window: (i64, i64, i64, i64),
    covers: &dyn Fn(i64, i64) -> bool,
) {
    for y in window.1..=window.3 {
        for x in window.0..=window.2 {
            if covers(x, y) {
                let b = setup
                    .bbox
                    .expect("twin covers a pixel of an empty primitive");
                assert!(
                    x >= b.x0 && x <= b.x1 && y >= b.y0 && y <= b.y1,
                    "({x}, {y}) covered outside the bbox {b:?}"
                );
            }
        }
    }
}

type Pts = Vec<(f64, f64)>;

/// Quantise f64 vertices; returns the raw vertices and the twin's view of them.
fn quantise(
    u: &PolygonInterpolator,
    pts: &[(f64, f64)],
    attrs: &[Vec<f64>],
) -> (Vec<Vertex>, Vec<twin::P>, Vec<Vec<f64>>) {
    let mut ctr = Counters::default();
    let k = u.attrs() as usize;
    let mut vs = Vec::new();
    let mut ps = Vec::new();
    let mut ats = Vec::new();
    for (i, &(x, y)) in pts.iter().enumerate() {
        let v = u
            .vertex_from_f64(i, x, y, &attrs[i][..k], &mut ctr)
            .unwrap();
        let (fx, fy, fa) = u.vertex_to_f64(&v);
        vs.push(v);
        ps.push([fx, fy]);
        ats.push(fa);
    }
    (vs, ps, ats)
}

fn pts_strategy(n: usize, lo: f64, hi: f64) -> impl Strategy<Value = Pts> {
    prop::collection::vec((lo..hi, lo..hi), n)
}

fn attrs_strategy(n: usize) -> impl Strategy<Value = Vec<Vec<f64>>> {
    prop::collection::vec(prop::collection::vec(-100.0..100.0f64, MAX_ATTRS), n)
}

fn run_triangle(u: &PolygonInterpolator, pts: &[(f64, f64)], attrs: &[Vec<f64>]) {
    let (vs, ps, ats) = quantise(u, pts, attrs);
    let tri = [ps[0], ps[1], ps[2]];
    let setup = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut Counters::default());
    let covers = |x, y| twin::triangle_covers(tri, x, y);
    let value = |i: usize, x, y| twin::triangle_value(tri, [ats[0][i], ats[1][i], ats[2][i]], x, y);
    check_walk(u, &setup, &covers, &value);
    check_bbox_holds_coverage(&setup, (-2, -2, 66, 66), &covers);
}

// ------------------------------------------------------------------ exhaustive

#[test]
fn exhaustive_all_triangles_on_a_3px_half_pixel_grid() {
    // s = 1: every triangle with vertices on the 7 × 7 half-pixel grid over 0 ..= 3 px,
    // both windings, all degenerate ones: 49³ = 117 649 ≤ 2^20 triangles.
    let u = PolygonInterpolatorConfig {
        attrs: 2,
        subpixel_bits: 1,
        coord_int_bits: 4,
        attr_fmt: s_fmt(8, 8),
        acc_int_bits: 10,
        acc_frac_bits: 5,
        out_int_bits: 8,
        out_frac_bits: 3,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap();
    let grid: Vec<(i64, i64)> = (0..49).map(|i| (i % 7, i / 7)).collect();
    let (mut covered_total, mut zeroed) = (0usize, 0usize);
    for a in &grid {
        for b in &grid {
            for c in &grid {
                let raw = [*a, *b, *c];
                let mut vs = [Vertex::default(); 3];
                for (i, &(x, y)) in raw.iter().enumerate() {
                    vs[i].x = x;
                    vs[i].y = y;
                    // Attribute codes in s8.8: a spread of values, some negative.
                    vs[i].attrs[0] = (x * 97 - y * 61 + i as i64 * 13) * 5;
                    vs[i].attrs[1] = -(x * 29 + y * 131) * 3 + 700;
                }
                let f: Vec<(f64, f64, Vec<f64>)> = vs.iter().map(|v| u.vertex_to_f64(v)).collect();
                let tri = [[f[0].0, f[0].1], [f[1].0, f[1].1], [f[2].0, f[2].1]];
                let setup = u.setup_triangle(&vs, &mut Counters::default());
                let covers = |x, y| twin::triangle_covers(tri, x, y);
                let value = |i: usize, x, y| {
                    twin::triangle_value(tri, [f[0].2[i], f[1].2[i], f[2].2[i]], x, y)
                };
                let (cov, outs) = check_walk(&u, &setup, &covers, &value);
                covered_total += cov.len();
                check_bbox_holds_coverage(&setup, (-1, -1, 4, 4), &covers);
                // The walk as the shafts passes feed it: rows run-length coded.
                let mut runs = Vec::new();
                for row in 0..setup.bbox.map_or(0, |b| b.height()) {
                    setup.row_runs(row, &mut runs);
                }
                let mut end = setup.state.clone();
                let mut ctr = Counters::default();
                run_span(&u, &mut end, &setup.moves(), &mut ctr);
                let case = RunsCase {
                    state: &setup.state,
                    runs: &runs,
                    out: &outs,
                    end: &end,
                    ctr: &ctr,
                    name: "walk rows",
                };
                zeroed += runs_agree_with_span(&u, &case);
            }
        }
    }
    assert!(covered_total > 100_000);
    assert!(
        zeroed > 1000,
        "blank closed-form runs write 0: {zeroed} words"
    );
}

// ------------------------------------------------------------------ error growth

#[test]
fn error_grows_with_span_length_and_stays_under_the_bound() {
    // A 4000 × 2 px sliver, attribute 0 → 120 across it: dA/dx = 0.03 per pixel, which
    // 4 fraction bits round to 0 (0.48 LSB): the error grows by 0.03 per pixel, just
    // under the bound's 2^-5 = 0.03125 per pixel.
    let narrow = PolygonInterpolatorConfig {
        attrs: 1,
        acc_int_bits: 12,
        acc_frac_bits: 4,
        out_int_bits: 12,
        out_frac_bits: 4,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap();
    let wide = PolygonInterpolatorConfig {
        acc_frac_bits: 32,
        acc_int_bits: 12,
        ..narrow.config()
    }
    .build()
    .unwrap();
    let pts = [(0.0, 0.0), (4000.0, 0.0), (0.0, 2.0)];
    let attrs = vec![vec![0.0], vec![120.0], vec![0.0]];
    let mut worst = Vec::new();
    for u in [&narrow, &wide] {
        let (vs, ps, ats) = quantise(u, &pts, &attrs);
        let tri = [ps[0], ps[1], ps[2]];
        let setup = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut Counters::default());
        assert_eq!(setup.pixels(), 8000);
        let covers = |x, y| twin::triangle_covers(tri, x, y);
        let value =
            |i: usize, x, y| twin::triangle_value(tri, [ats[0][i], ats[1][i], ats[2][i]], x, y);
        let (_, outs) = check_walk(u, &setup, &covers, &value);
        // Largest error in each 500-pixel stretch of the first row.
        let mut buckets = [0.0f64; 6];
        for o in outs.iter().filter(|o| o.inside && o.y == 0) {
            let e = (u.out_to_f64(o.attrs[0]) - value(0, o.x, o.y)).abs();
            let b = (o.x / 500) as usize;
            buckets[b] = buckets[b].max(e);
        }
        println!(
            "acc_frac_bits {}: max error per 500 px of span: {buckets:.4?}",
            u.acc_frac_bits()
        );
        worst.push(buckets);
    }
    let n = worst[0];
    assert!(
        n.windows(2).all(|w| w[1] > w[0]),
        "error must rise with span: {n:?}"
    );
    assert!(n[5] > 80.0 && n[0] < 16.0, "{n:?}");
    // 32 fraction bits: the accumulated part stays far below one output LSB.
    assert!(
        worst[1].iter().all(|&e| e <= 1.0 / 32.0 + SLACK),
        "{:?}",
        worst[1]
    );
}

// ------------------------------------------------------------------ properties

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    #[test]
    fn triangles_within_bound_default_wide_narrow(
        ci in 0usize..3,
        k in 1u32..=MAX_ATTRS as u32,
        pts in pts_strategy(3, 0.0, 64.0),
        attrs in attrs_strategy(3),
    ) {
        let u = config_by_index(ci, k);
        run_triangle(&u, &pts, &attrs);
    }

    #[test]
    fn gl_quads_cover_once_and_within_bound(
        ci in 0usize..3,
        k in 1u32..=MAX_ATTRS as u32,
        (x0, y0, w, h) in (0.0..40.0f64, 0.0..40.0f64, 4.0..24.0f64, 4.0..24.0f64),
        jitter in prop::collection::vec((-3.0..3.0f64, -3.0..3.0f64), 4),
        attrs in attrs_strategy(4),
        ccw in any::<bool>(),
    ) {
        let u = config_by_index(ci, k);
        let mut pts = vec![(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)];
        if ccw {
            pts.reverse();
        }
        for (p, j) in pts.iter_mut().zip(&jitter) {
            p.0 += j.0;
            p.1 += j.1;
        }
        let (vs, ps, ats) = quantise(&u, &pts, &attrs);
        let q = [ps[0], ps[1], ps[2], ps[3]];
        let halves = u.setup_quad(&[vs[0], vs[1], vs[2], vs[3]], &mut Counters::default());
        let mut all = Vec::new();
        for (t, setup) in halves.iter().enumerate() {
            let (a, b, c) = if t == 0 { (0, 1, 2) } else { (0, 2, 3) };
            let tri = [q[a], q[b], q[c]];
            let covers = |x, y| twin::triangle_covers(tri, x, y);
            let value = |i: usize, x, y| twin::triangle_value(tri, [ats[a][i], ats[b][i], ats[c][i]], x, y);
            let (cov, _) = check_walk(&u, setup, &covers, &value);
            all.extend(cov);
        }
        // Convex quad: the shared edge's pixels go to exactly one triangle, and the
        // union is the twin's quad coverage.
        let convex = (0..4).all(|i| twin::area2([q[i], q[(i + 1) % 4], q[(i + 2) % 4]]) > 0.0)
            || (0..4).all(|i| twin::area2([q[i], q[(i + 1) % 4], q[(i + 2) % 4]]) < 0.0);
        if convex {
            let n = all.len();
            all.sort_unstable();
            all.dedup();
            prop_assert_eq!(all.len(), n, "a pixel covered twice");
            let twin_count = (-5..75i64)
                .flat_map(|y| (-5..75i64).map(move |x| (x, y)))
                .filter(|&(x, y)| twin::quad_covers(q, x, y).is_some())
                .count();
            prop_assert_eq!(n, twin_count);
        }
    }

    #[test]
    fn parallelograms_within_bound_and_equal_to_the_gl_split(
        ci in 0usize..3,
        k in 1u32..=MAX_ATTRS as u32,
        pts in pts_strategy(3, 8.0, 40.0),
        attrs in attrs_strategy(3),
    ) {
        let u = config_by_index(ci, k);
        let (vs, ps, ats) = quantise(&u, &pts, &attrs);
        let v = [ps[0], ps[1], ps[2]];
        let mut ctr = Counters::default();
        let setup = u.setup_parallelogram(&[vs[0], vs[1], vs[2]], &mut ctr).unwrap();
        let covers = |x, y| twin::parallelogram_covers(v, x, y);
        let value = |i: usize, x, y| twin::parallelogram_value(v, [ats[0][i], ats[1][i], ats[2][i]], x, y);
        let (mut cov, _) = check_walk(&u, &setup, &covers, &value);
        check_bbox_holds_coverage(&setup, (-2, -2, 82, 82), &covers);
        // The same quad given with its 4th vertex, through the consistency check, and as
        // a GL split: identical coverage (the diagonal is shared exactly once).
        let mut v3 = vs[0];
        v3.x = vs[0].x + vs[2].x - vs[1].x;
        v3.y = vs[0].y + vs[2].y - vs[1].y;
        for i in 0..MAX_ATTRS {
            v3.attrs[i] = vs[0].attrs[i] + vs[2].attrs[i] - vs[1].attrs[i];
        }
        let quad = [vs[0], vs[1], vs[2], v3];
        let again = u.setup_affine_quad(&quad, &mut ctr).unwrap();
        prop_assert_eq!(&again, &setup);
        let mut split = Vec::new();
        for h in u.setup_quad(&quad, &mut ctr) {
            let mut st = h.state.clone();
            let outs = run_span(&u, &mut st, &h.moves(), &mut Counters::default());
            split.extend(outs.iter().filter(|o| o.inside).map(|o| (o.x, o.y)));
        }
        cov.sort_unstable();
        split.sort_unstable();
        prop_assert_eq!(cov, split);
    }

    #[test]
    fn tick_and_span_drivers_agree(
        k in 0u32..=MAX_ATTRS as u32,
        s in 0u32..=8,
        acc_frac in 1u32..=40,
        acc_int in 1u32..=22,
        out_frac in 0u32..=12,
        signed in any::<bool>(),
        mode in prop::sample::select(Overflow::ALL.to_vec()),
        pts in pts_strategy(3, 0.0, 12.0),
        attrs in attrs_strategy(3),
        extra in prop::collection::vec(0u8..4, 0..30),
    ) {
        let u = PolygonInterpolatorConfig {
            attrs: k,
            subpixel_bits: s,
            attr_fmt: Format { int_bits: 10, frac_bits: 8, signed },
            acc_int_bits: acc_int,
            acc_frac_bits: acc_frac,
            acc_overflow: mode,
            out_int_bits: 10,
            out_frac_bits: out_frac,
            ..PolygonInterpolatorConfig::default()
        }
        .build()
        .unwrap();
        let mut ctr = Counters::default();
        let vs: Vec<Vertex> = (0..3)
            .map(|i| u.vertex_from_f64(i, pts[i].0, pts[i].1, &attrs[i][..k as usize], &mut ctr).unwrap())
            .collect();
        let setup = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut ctr);
        // The serpentine walk, then arbitrary moves (beyond the bbox too).
        let mut moves = setup.moves();
        moves.extend(extra.iter().map(|&m| [Move::Hold, Move::Right, Move::Left, Move::Down][m as usize]));
        common::assert_drivers_agree(&u, setup.state.clone(), &moves);
        lanes_agree_with_span(&u, &setup.state, &moves);
    }

    /// The batch kernel's closed-form runs: long runs of one move over narrow
    /// accumulators (so some runs wrap or saturate part-way and take the per-step
    /// path), every rounding mode, big primitives walked row by row.
    #[test]
    fn batch_runs_agree_with_span_and_tick(
        k in 1u32..=6,
        acc_frac in 9u32..=30,
        acc_int in 1u32..=14,
        out_frac in 0u32..=8,
        signed in any::<bool>(),
        mode in prop::sample::select(Overflow::ALL.to_vec()),
        q in prop::sample::select(Quant::ALL.to_vec()),
        pts in pts_strategy(3, -20.0, 90.0),
        attrs in attrs_strategy(3),
        runs in prop::collection::vec((0u8..4, 1usize..60), 0..8),
    ) {
        let u = PolygonInterpolatorConfig {
            attrs: k,
            attr_fmt: Format { int_bits: 10, frac_bits: 8, signed },
            acc_int_bits: acc_int,
            acc_frac_bits: acc_frac,
            acc_overflow: mode,
            out_int_bits: 10,
            out_frac_bits: out_frac,
            out_quant: q,
            ..PolygonInterpolatorConfig::default()
        }
        .build()
        .unwrap();
        let mut ctr = Counters::default();
        let vs: Vec<Vertex> = (0..3)
            .map(|i| u.vertex_from_f64(i, pts[i].0, pts[i].1, &attrs[i][..k as usize], &mut ctr).unwrap())
            .collect();
        let setup = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut ctr);
        let mut moves = Vec::new();
        for row in 0..setup.bbox.map_or(0, |b| b.height()) {
            setup.row_moves(row, &mut moves);
        }
        prop_assert_eq!(&moves, &setup.moves());
        let mut row_runs = Vec::new();
        for row in 0..setup.bbox.map_or(0, |b| b.height()) {
            setup.row_runs(row, &mut row_runs);
        }
        let decoded: Vec<Move> = row_runs.iter().flat_map(|&(m, n)| std::iter::repeat_n(m, n)).collect();
        prop_assert_eq!(&decoded, &moves);
        for &(m, n) in &runs {
            moves.extend(std::iter::repeat_n([Move::Hold, Move::Right, Move::Left, Move::Down][m as usize], n));
        }
        common::assert_drivers_agree(&u, setup.state.clone(), &moves);
        lanes_agree_with_span(&u, &setup.state, &moves);
    }

    #[test]
    fn random_configs_never_panic_and_errors_name_the_field(
        attrs in 0u32..20,
        s in 0u32..12,
        c in 0u32..20,
        ai in 0u32..40,
        af in 0u32..40,
        asg in any::<bool>(),
        acc_int in 0u32..64,
        acc_frac in 0u32..64,
        out_int in 0u32..50,
        out_frac in 0u32..50,
        q in prop::sample::select(Quant::ALL.to_vec()),
        o in prop::sample::select(Overflow::ALL.to_vec()),
        raw in prop::collection::vec((any::<i64>(), any::<i64>(), any::<[i64; MAX_ATTRS]>()), 4),
    ) {
        let cfg = PolygonInterpolatorConfig {
            attrs,
            subpixel_bits: s,
            coord_int_bits: c,
            attr_fmt: Format { int_bits: ai, frac_bits: af, signed: asg },
            acc_int_bits: acc_int,
            acc_frac_bits: acc_frac,
            acc_overflow: o,
            out_int_bits: out_int,
            out_frac_bits: out_frac,
            out_quant: q,
            // The barycentric mode on odd attribute counts, weight bits 0 ..= 17 (0 and
            // 17 invalid).
            barycentric: (attrs % 2 == 1).then_some(Barycentric {
                weight_bits: out_frac % 18,
                strict: s % 2 == 0,
            }),
        };
        match cfg.build() {
            Err(e) => prop_assert!(e.field().starts_with("polygon_interpolator."), "{}", e.field()),
            Ok(u) => {
                // Any raw input words: setup and a few moves must not panic.
                let vs: Vec<Vertex> = raw.iter().map(|&(x, y, a)| Vertex { x, y, attrs: a }).collect();
                let mut ctr = Counters::default();
                let t = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut ctr);
                let _ = u.setup_quad(&[vs[0], vs[1], vs[2], vs[3]], &mut ctr);
                let _ = u.setup_parallelogram(&[vs[0], vs[1], vs[2]], &mut ctr);
                let _ = u.setup_affine_quad(&[vs[0], vs[1], vs[2], vs[3]], &mut ctr);
                let mut st = t.state.clone();
                let moves = [Move::Hold, Move::Right, Move::Down, Move::Left, Move::Left, Move::Down];
                let _ = run_span(&u, &mut st, &moves, &mut ctr);
            }
        }
    }

    #[test]
    fn non_finite_vertex_inputs_name_the_field(
        bad in prop::sample::select(vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
        which in 0usize..3,
        idx in 0usize..4,
        j in 0usize..4,
    ) {
        let u = cfg_default(4);
        let mut a = [1.0, 2.0, 3.0, 4.0];
        let (mut x, mut y) = (1.0, 2.0);
        let want = match which {
            0 => { x = bad; format!("polygon_interpolator.vertices[{idx}].x") }
            1 => { y = bad; format!("polygon_interpolator.vertices[{idx}].y") }
            _ => { a[j] = bad; format!("polygon_interpolator.vertices[{idx}].attrs[{j}]") }
        };
        let e = u.vertex_from_f64(idx, x, y, &a, &mut Counters::default()).unwrap_err();
        prop_assert_eq!(e.field(), want.as_str());
    }
}

// ------------------------------------------------------------------ edge cases

#[test]
fn config_errors_name_their_fields() {
    let d = PolygonInterpolatorConfig::default();
    let cases: Vec<(PolygonInterpolatorConfig, &str)> = vec![
        (PolygonInterpolatorConfig { attrs: 17, ..d }, "attrs"),
        (
            PolygonInterpolatorConfig {
                subpixel_bits: 9,
                ..d
            },
            "subpixel_bits",
        ),
        (
            PolygonInterpolatorConfig {
                coord_int_bits: 15,
                ..d
            },
            "coord_int_bits",
        ),
        (
            PolygonInterpolatorConfig {
                attr_fmt: s_fmt(20, 16),
                ..d
            },
            "attr_fmt",
        ),
        (
            PolygonInterpolatorConfig {
                attr_fmt: Format {
                    int_bits: 0,
                    frac_bits: 8,
                    signed: true,
                },
                ..d
            },
            "attr_fmt",
        ),
        (
            PolygonInterpolatorConfig {
                acc_int_bits: 0,
                ..d
            },
            "acc_int_bits",
        ),
        (
            PolygonInterpolatorConfig {
                acc_frac_bits: 41,
                ..d
            },
            "acc_frac_bits",
        ),
        (
            PolygonInterpolatorConfig {
                acc_int_bits: 30,
                acc_frac_bits: 40,
                ..d
            },
            "acc_int_bits",
        ),
        (
            PolygonInterpolatorConfig {
                out_frac_bits: 41,
                ..d
            },
            "out_frac_bits",
        ),
        (
            PolygonInterpolatorConfig {
                out_int_bits: 0,
                ..d
            },
            "out_int_bits",
        ),
    ];
    for (c, f) in cases {
        let e = c.build().unwrap_err();
        assert_eq!(e.field(), format!("polygon_interpolator.{f}"), "{e}");
    }
    assert_eq!(
        PolygonInterpolator::new(d).unwrap(),
        PolygonInterpolator::geforce()
    );
}

#[test]
fn vertex_helper_errors() {
    let u = cfg_default(2);
    let mut ctr = Counters::default();
    let e = u
        .vertex_from_f64(2, 5000.0, 0.0, &[0.0, 0.0], &mut ctr)
        .unwrap_err();
    assert_eq!(e.field(), "polygon_interpolator.vertices[2].x");
    // The position and the coordinate range in pixels, as the scene writes them:
    // s13.4 holds −4 096 ..= 4 096 − 1/16.
    assert!(
        matches!(e, rtl_model::ConfigError::OutOfRange { value, min, max, .. }
            if (value, min, max) == (5000.0, -4096.0, 4096.0 - 0.0625)),
        "{e}"
    );
    let e = u
        .vertex_from_f64(1, 0.0, -4097.0, &[0.0, 0.0], &mut ctr)
        .unwrap_err();
    assert_eq!(e.field(), "polygon_interpolator.vertices[1].y");
    let e = u
        .vertex_from_f64(1, 0.0, 0.0, &[0.0], &mut ctr)
        .unwrap_err();
    assert_eq!(e.field(), "polygon_interpolator.vertices[1].attrs");
    // An attribute beyond s16.16 saturates, counted.
    u.vertex_from_f64(0, 0.0, 0.0, &[1e9, 0.0], &mut ctr)
        .unwrap();
    assert_eq!(ctr.saturations, 1);
    // Parallelogram whose implied 4th vertex leaves the coordinate range.
    let v = |x: f64, y: f64| {
        u.vertex_from_f64(0, x, y, &[0.0, 0.0], &mut Counters::default())
            .unwrap()
    };
    let e = u
        .setup_parallelogram(
            &[v(4000.0, 0.0), v(-4000.0, 0.0), v(4000.0, 10.0)],
            &mut ctr,
        )
        .unwrap_err();
    assert_eq!(e.field(), "polygon_interpolator.vertices[3].x");
    // A quad that is not an affine parallelogram.
    let mut q = [v(0.0, 0.0), v(8.0, 0.0), v(8.0, 8.0), v(0.0, 8.0)];
    assert!(u.setup_affine_quad(&q, &mut ctr).is_ok());
    q[3].attrs[1] = 7;
    let e = u.setup_affine_quad(&q, &mut ctr).unwrap_err();
    assert_eq!(e.field(), "polygon_interpolator.vertices[3].attrs[1]");
    q[3].y += 1;
    let e = u.setup_affine_quad(&q, &mut ctr).unwrap_err();
    assert_eq!(e.field(), "polygon_interpolator.vertices[3].y");
}

#[test]
fn degenerate_primitives_give_no_pixels() {
    let u = cfg_default(3);
    let mut ctr = Counters::default();
    let v = |x: f64, y: f64| {
        u.vertex_from_f64(0, x, y, &[1.0, -2.0, 3.0], &mut Counters::default())
            .unwrap()
    };
    for tri in [
        [v(0.0, 0.0), v(10.0, 10.0), v(20.0, 20.0)], // collinear
        [v(5.0, 5.0), v(5.0, 5.0), v(5.0, 5.0)],     // a point
        [v(3.0, 1.0), v(3.0, 1.0), v(9.0, 2.0)],     // two coincident
    ] {
        let s = u.setup_triangle(&tri, &mut ctr);
        assert_eq!(s.bbox, None);
        assert!(s.moves().is_empty());
        let p = u.setup_parallelogram(&tri, &mut ctr).unwrap();
        assert!(p.moves().is_empty());
        // Even driven anyway, an empty primitive never covers a pixel.
        let mut st = s.state.clone();
        let moves = [Move::Hold, Move::Right, Move::Down, Move::Left];
        let outs = run_span(&u, &mut st, &moves, &mut ctr);
        assert!(outs.iter().all(|o| !o.inside));
    }
    // Non-degenerate but between pixel centres: no moves either.
    let s = u.setup_triangle(&[v(0.6, 0.6), v(1.4, 0.6), v(0.6, 1.4)], &mut ctr);
    assert_eq!(s.bbox, None);
    assert_eq!(ctr.saturations + ctr.overflows, 0);
}

#[test]
fn accumulator_overflow_is_counted_never_silent() {
    // Attributes ±100 in a 4-integer-bit accumulator (±8).
    for mode in [Overflow::Wrap, Overflow::Sat] {
        let u = PolygonInterpolatorConfig {
            attrs: 1,
            acc_int_bits: 4,
            acc_frac_bits: 8,
            acc_overflow: mode,
            out_int_bits: 8,
            ..PolygonInterpolatorConfig::default()
        }
        .build()
        .unwrap();
        let mut ctr = Counters::default();
        let v = |x: f64, y: f64, a: f64| {
            u.vertex_from_f64(0, x, y, &[a], &mut Counters::default())
                .unwrap()
        };
        let s = u.setup_triangle(
            &[v(0.0, 0.0, 0.0), v(30.0, 0.0, 100.0), v(0.0, 30.0, -100.0)],
            &mut ctr,
        );
        let mut st = s.state.clone();
        run_span(&u, &mut st, &s.moves(), &mut ctr);
        match mode {
            Overflow::Wrap => assert!(ctr.overflows > 0 && ctr.saturations == 0, "{ctr:?}"),
            _ => assert!(ctr.saturations > 0 && ctr.overflows == 0, "{ctr:?}"),
        }
    }
}

/// Runs of every move long enough to wrap the pixel counters (2 ..= 4 integer bits)
/// and, in a 3-integer-bit accumulator, the attributes: the batch kernel's and the
/// lane forms' closed-form runs must fall back to the kernel where a register wraps
/// or saturates, with the drivers' words, final state and counters.
#[test]
fn runs_of_every_move_wrap_the_counters_as_the_kernel_does() {
    for c in 2..=4u32 {
        for mode in [Overflow::Wrap, Overflow::Sat] {
            let u = PolygonInterpolatorConfig {
                attrs: 2,
                subpixel_bits: 1,
                coord_int_bits: c,
                acc_int_bits: 3,
                acc_frac_bits: 6,
                acc_overflow: mode,
                out_int_bits: 8,
                out_frac_bits: 2,
                ..PolygonInterpolatorConfig::default()
            }
            .build()
            .unwrap();
            let lim = (1i64 << (c - 1)) as f64 - 0.5;
            let v = |x: f64, y: f64, a: [f64; 2]| {
                u.vertex_from_f64(0, x, y, &a, &mut Counters::default())
                    .unwrap()
            };
            let s = u.setup_triangle(
                &[
                    v(-lim, -lim, [0.0, 3.0]),
                    v(lim, -lim, [20.0, -3.0]),
                    v(-lim, lim, [-20.0, 1.0]),
                ],
                &mut Counters::default(),
            );
            for m in [Move::Hold, Move::Right, Move::Left, Move::Down] {
                for n in 1..=3 * (1usize << c) {
                    let mut moves = s.moves();
                    moves.extend(std::iter::repeat_n(m, n));
                    common::assert_drivers_agree(&u, s.state.clone(), &moves);
                    lanes_agree_with_span(&u, &s.state, &moves);
                }
            }
        }
    }
}

/// `cfg` with a narrow output, s4.2, rounded in mode `q`: attributes of a few
/// units reach its range and its zero code.
fn narrow_out(cfg: PolygonInterpolatorConfig, q: Quant) -> PolygonInterpolator {
    PolygonInterpolatorConfig {
        out_int_bits: 4,
        out_frac_bits: 2,
        out_quant: q,
        ..cfg
    }
    .build()
    .unwrap()
}

/// The closed-form runs' event-free form (a run whose first and last codes are in
/// range and of one strict sign is written without counting): on one triangle, an
/// attribute that stays positive (every run event-free), one that crosses zero
/// (rounds to 0 on the way: underflows), one that leaves the output range part-way
/// (saturations) and one that stays negative, in every rounding mode: the lane forms
/// give the drivers' words, final state and counters, and the events are there.
#[test]
fn event_free_runs_and_runs_with_events_agree_with_the_drivers() {
    for q in Quant::ALL {
        let u = narrow_out(
            PolygonInterpolatorConfig {
                attrs: 4,
                attr_fmt: Format {
                    int_bits: 10,
                    frac_bits: 8,
                    signed: true,
                },
                ..PolygonInterpolatorConfig::default()
            },
            q,
        );
        let v = |x: f64, y: f64, a: [f64; 4]| {
            u.vertex_from_f64(0, x, y, &a, &mut Counters::default())
                .unwrap()
        };
        let s = u.setup_triangle(
            &[
                v(0.0, 0.0, [1.0, -0.4, -12.0, -1.0]),
                v(60.0, 0.0, [5.0, 0.4, 12.0, -5.0]),
                v(0.0, 40.0, [3.0, 0.2, 0.0, -3.0]),
            ],
            &mut Counters::default(),
        );
        let moves = s.moves();
        let mut c = Counters::default();
        rtl_model::driver::run_span(&u, &mut s.state.clone(), &moves, &mut c);
        assert!(c.underflows > 0, "{q:?}: the zero crossing must underflow");
        assert!(
            c.saturations > 0,
            "{q:?}: the third attribute must saturate"
        );
        common::assert_drivers_agree(&u, s.state.clone(), &moves);
        lanes_agree_with_span(&u, &s.state, &moves);
    }
}

#[test]
fn wrapped_gradients_still_give_exact_in_range_pixels() {
    // Diagonal slivers ~0.2 px thick with the attribute rising 100 across them: the
    // gradients (over a hundred per pixel) overflow an 8-integer-bit accumulator (±128),
    // yet WRAP arithmetic is modular, so covered pixels (true values in 0 ..= 100) still
    // meet the bound.
    let u = PolygonInterpolatorConfig {
        attrs: 1,
        acc_int_bits: 8,
        acc_frac_bits: 8,
        out_int_bits: 9,
        out_frac_bits: 4,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap();
    let mut setup_ctr = Counters::default();
    let mut covered = 0;
    for (len, off) in [(30.0, 0.25), (45.0, 0.3), (20.0, 0.2), (60.0, 0.35)] {
        // Gradient components ≈ 100 / (2·off) ≥ 140 per pixel: beyond ±128.
        let pts = [
            (0.5, 0.25),
            (len + 0.5, len + 0.25),
            (0.5 - off, 0.25 + off),
        ];
        let attrs = vec![vec![0.0], vec![0.0], vec![100.0]];
        let (vs, ps, ats) = quantise(&u, &pts, &attrs);
        let tri = [ps[0], ps[1], ps[2]];
        let setup = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut setup_ctr);
        let covers = |x, y| twin::triangle_covers(tri, x, y);
        let value =
            |i: usize, x, y| twin::triangle_value(tri, [ats[0][i], ats[1][i], ats[2][i]], x, y);
        covered += check_walk(&u, &setup, &covers, &value).0.len();
        let mut st = setup.state.clone();
        run_span(&u, &mut st, &setup.moves(), &mut setup_ctr);
    }
    assert!(covered > 50, "{covered}");
    assert!(setup_ctr.overflows > 0, "{setup_ctr:?}");
    // The gradients themselves wrapped (not only extrapolated bounding-box pixels).
    let g = |off: f64| {
        let pts = [(0.5, 0.25), (30.5, 30.25), (0.5 - off, 0.25 + off)];
        let (vs, _, _) = quantise(&u, &pts, &[vec![0.0], vec![0.0], vec![100.0]]);
        let mut c = Counters::default();
        u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut c);
        c.overflows
    };
    assert!(g(0.25) >= 2);
}

#[test]
fn widest_config_extreme_vertices_do_not_overflow_setup() {
    // c = 14, s = 8, 32-bit attributes with 0 and with 32 fraction bits, 40 accumulator
    // fraction bits: the setup's i128 products at their largest (overflow checks are on
    // in the test profile).
    for (attr_fmt, acc_int) in [
        (s_fmt(32, 0), 22),
        (
            Format {
                int_bits: 32,
                frac_bits: 0,
                signed: false,
            },
            22,
        ),
        (
            Format {
                int_bits: 0,
                frac_bits: 32,
                signed: false,
            },
            22,
        ),
        (s_fmt(1, 31), 22),
    ] {
        let u = PolygonInterpolatorConfig {
            attrs: 8,
            subpixel_bits: 8,
            coord_int_bits: 14,
            attr_fmt,
            acc_int_bits: acc_int,
            acc_frac_bits: 40,
            out_int_bits: 8,
            out_frac_bits: 40,
            ..PolygonInterpolatorConfig::default()
        }
        .build()
        .unwrap();
        let (lo, hi) = (-(1i64 << 21), (1i64 << 21) - 1);
        let (amin, amax) = (attr_fmt.min_raw() as i64, attr_fmt.max_raw() as i64);
        let corners = [(lo, lo), (hi, lo), (hi, hi), (lo, hi), (0, lo), (hi, 0)];
        let mut ctr = Counters::default();
        for a in &corners {
            for b in &corners {
                for c in &corners {
                    let mk = |p: &(i64, i64), at: i64| Vertex {
                        x: p.0,
                        y: p.1,
                        attrs: [at; MAX_ATTRS],
                    };
                    let t = u.setup_triangle(&[mk(a, amin), mk(b, amax), mk(c, amin)], &mut ctr);
                    let mut st = t.state.clone();
                    run_span(
                        &u,
                        &mut st,
                        &[Move::Hold, Move::Right, Move::Down, Move::Left],
                        &mut ctr,
                    );
                    let _ =
                        u.setup_parallelogram(&[mk(a, amax), mk(b, amin), mk(c, amax)], &mut ctr);
                }
            }
        }
    }
}

#[test]
fn serpentine_moves_visit_every_bbox_pixel_once() {
    let u = cfg_default(1);
    let v = |x: f64, y: f64| {
        u.vertex_from_f64(0, x, y, &[0.0], &mut Counters::default())
            .unwrap()
    };
    let s = u.setup_triangle(
        &[v(1.2, 2.7), v(9.9, 3.1), v(4.0, 8.8)],
        &mut Counters::default(),
    );
    let b = s.bbox.unwrap();
    let mut st = s.state.clone();
    let outs = run_span(&u, &mut st, &s.moves(), &mut Counters::default());
    let mut seen: Vec<(i64, i64)> = outs.iter().map(|o| (o.x, o.y)).collect();
    seen.sort_unstable();
    let mut want: Vec<(i64, i64)> = (b.y0..=b.y1)
        .flat_map(|y| (b.x0..=b.x1).map(move |x| (x, y)))
        .collect();
    want.sort_unstable();
    assert_eq!(seen, want);
}

#[test]
fn print_datasheet_numbers() {
    // cargo test --test polygon_interpolator print_datasheet_numbers -- --nocapture
    // prints the datasheet's figures; the test fails when docs/units.md no longer
    // quotes them.
    use common::docs::{assert_quotes, grouped, section};
    let doc = section("units.md", "## polygon_interpolator");
    let at = "docs/units.md, section polygon_interpolator,";
    for (name, u) in [
        ("default", PolygonInterpolator::geforce()),
        ("wide", cfg_wide(4)),
        ("narrow", cfg_narrow(4)),
    ] {
        let s = UnitSummary::of(&u);
        let setup: f64 = s
            .breakdown
            .iter()
            .filter(|(n, _)| n.starts_with("setup:"))
            .map(|(_, g)| g)
            .sum();
        println!(
            "{name}: latency {} II {} gates {:.0} (walker {:.0}, setup {:.0}) ram_bits {} edge_bits {} setup_cycles {}",
            s.latency,
            s.ii,
            s.gates_nand2,
            s.gates_nand2 - setup,
            setup,
            s.ram_bits,
            u.edge_bits(),
            u.setup_cycles()
        );
        // The cost table's row: walker | setup | total.
        let row = format!(
            "| {} | {} | {} |",
            grouped(s.gates_nand2 - setup),
            grouped(setup),
            grouped(s.gates_nand2)
        );
        assert_quotes(&doc, &row, at);
        if name == "default" {
            assert_quotes(&doc, &format!("Latency **{}**", s.latency), at);
            assert_quotes(&doc, &format!("**II {}**", s.ii), at);
            assert_quotes(&doc, &format!("({} at defaults)", u.setup_cycles()), at);
            assert_quotes(&doc, &format!("edges {} b", u.edge_bits()), at);
            // The breakdown paragraph quotes every part, in order.
            let para = &doc[doc.find("Default breakdown:").expect("breakdown paragraph")..];
            let mut from = 0;
            for (part, g) in &s.breakdown {
                println!("  {part}: {g:.0}");
                let q = format!(" {}", grouped(*g));
                let k = para[from..].find(&q).unwrap_or_else(|| {
                    panic!("{at} breakdown no longer quotes {part} = {}", grouped(*g))
                });
                from += k + q.len();
            }
        }
    }
    // Gates by the configured attribute count (default widths otherwise).
    let gates = |k: u32| UnitSummary::of(&cfg_default(k)).gates_nand2;
    for k in [0, 1, 2, 4, 8, 10, 16] {
        println!(
            "default widths, K = {k}: gates {:.0}, setup_cycles {}",
            gates(k),
            cfg_default(k).setup_cycles()
        );
    }
    let by_k: Vec<String> = [0, 2, 4, 8, 10, 16]
        .iter()
        .map(|&k| format!("{k} {}", grouped(gates(k))))
        .collect();
    assert_quotes(&doc, &format!("K = {}", by_k.join(", ")), at);
    assert_quotes(
        &doc,
        &format!("{} per attribute", grouped(gates(1) - gates(0))),
        at,
    );
}

#[test]
fn attribute_channels_do_not_depend_on_the_attribute_count() {
    // Attribute i comes out the same whatever K > i: a unit carrying 2 more channels
    // (the envmap render's (u, v): 10, not 8) leaves the first 8 bit for bit.
    let mut rng = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = |m: i64| {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng % (2 * m as u64 + 1)) as i64 - m
    };
    for cfg in [cfg_default, cfg_wide, cfg_narrow] {
        let (u8_, u10, u16_) = (cfg(8), cfg(10), cfg(MAX_ATTRS as u32));
        for _ in 0..50 {
            let mut v = [Vertex::default(); 3];
            for vk in &mut v {
                vk.x = next(40 << u16_.subpixel_bits());
                vk.y = next(40 << u16_.subpixel_bits());
                for a in &mut vk.attrs {
                    *a = next(1 << 24);
                }
            }
            let walk = |u: &PolygonInterpolator| {
                let mut ctr = Counters::default();
                let s = u.setup_triangle(&v, &mut ctr);
                run_span(u, &mut s.state.clone(), &s.moves(), &mut ctr)
            };
            let (o8, o10, o16) = (walk(&u8_), walk(&u10), walk(&u16_));
            assert_eq!(o8.len(), o16.len());
            for ((a, b), c) in o8.iter().zip(&o10).zip(&o16) {
                assert_eq!((a.x, a.y, a.inside), (c.x, c.y, c.inside));
                assert_eq!(a.attrs[..8], c.attrs[..8]);
                assert_eq!(b.attrs[..10], c.attrs[..10]);
                assert!(a.attrs[8..].iter().all(|&z| z == 0));
            }
        }
    }
}

#[test]
fn cost_depends_on_the_configured_attrs_only() {
    // MAX_ATTRS sizes the arrays and bounds the config; the hardware is the configured
    // K: every attribute adds the same channel (accumulator, rounder, output register
    // bits), and K = 0 has none.
    for cfg in [cfg_default, cfg_wide, cfg_narrow] {
        let g: Vec<f64> = (0..=MAX_ATTRS as u32)
            .map(|k| UnitSummary::of(&cfg(k)).gates_nand2)
            .collect();
        let step = g[1] - g[0];
        assert!(step > 0.0);
        for k in 1..=MAX_ATTRS {
            assert!(
                ((g[k] - g[k - 1]) - step).abs() < 1e-6 * g[k],
                "K = {k}: {} vs {step}",
                g[k] - g[k - 1]
            );
        }
        assert_eq!(
            cfg(MAX_ATTRS as u32).setup_cycles() - cfg(0).setup_cycles(),
            3 * MAX_ATTRS as u32
        );
    }
}

/// A parallelogram's implied fourth vertex v3 = v0 + v2 − v1 may sit on either end of
/// the coordinate range; one code beyond it is refused naming the coordinate.
#[test]
fn the_implied_fourth_vertex_may_reach_the_ends_of_the_coordinate_range() {
    let u = PolygonInterpolatorConfig {
        attrs: 1,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap();
    let (lo, hi) = (u.pos_fmt().min_raw() as i64, u.pos_fmt().max_raw() as i64);
    let v = |x: i64, y: i64| raw_vertex(x, y, &[]);
    // v0 + v2 − v1 = (x3, y3) with every given vertex in range.
    let implied = |x3: i64, y3: i64| [v(x3 / 2, y3 / 2), v(0, 0), v(x3 - x3 / 2, y3 - y3 / 2)];
    for (x3, y3) in [(lo, 40), (hi, 40), (40, lo), (40, hi)] {
        let r = u.setup_parallelogram(&implied(x3, y3), &mut Counters::default());
        assert!(r.is_ok(), "v3 = ({x3}, {y3})");
    }
    for (x3, y3, field) in [
        (lo - 1, 40, "x"),
        (hi + 1, 40, "x"),
        (40, lo - 1, "y"),
        (40, hi + 1, "y"),
    ] {
        let e = u
            .setup_parallelogram(&implied(x3, y3), &mut Counters::default())
            .unwrap_err();
        assert_eq!(
            e.field(),
            format!("polygon_interpolator.vertices[3].{field}"),
            "v3 = ({x3}, {y3})"
        );
        // The error gives the coordinate and the range in pixels, as the scene writes them.
        let lsb = (-(u.subpixel_bits() as f64)).exp2();
        let given = if field == "x" { x3 } else { y3 } as f64 * lsb;
        let range = (lo as f64 * lsb, hi as f64 * lsb);
        assert!(
            matches!(e, rtl_model::ConfigError::OutOfRange { value, min, max, .. }
                if value == given && (min, max) == range),
            "{e}"
        );
    }
}

/// The barycentric mode at attribute formats with 1 ..= 3 integer bits: a constant
/// attribute (0.5) comes out exactly at every covered pixel (the widened intermediate
/// format holds the integer bits plus 3).
#[test]
fn barycentric_mode_runs_at_attribute_formats_with_few_integer_bits() {
    for int_bits in 1..=3u32 {
        let u = PolygonInterpolatorConfig {
            attrs: 1,
            attr_fmt: Format {
                int_bits,
                frac_bits: 8,
                signed: true,
            },
            barycentric: Some(NV2A_WEIGHTS),
            ..PolygonInterpolatorConfig::default()
        }
        .build()
        .unwrap();
        let (outs, _) = walk_triangle(&u, [(1.0, 1.0), (12.0, 2.5), (4.0, 9.0)], &[0.5]);
        assert!(outs.iter().any(|o| o.inside), "int_bits {int_bits}");
        for o in outs.iter().filter(|o| o.inside) {
            assert_eq!(u.out_to_f64(o.attrs[0]), 0.5, "int_bits {int_bits}");
        }
    }
}

/// The 2-bit move code on the input wire is the one polygon_interpolator.v decodes
/// (`hold`, `lf`, `dn` by their codes; right is the fourth).
#[test]
fn move_codes_are_the_ones_the_verilog_decodes() {
    let v = include_str!("../rtl_model/verilog/units/polygon_interpolator.v");
    let code_of = |wire: &str| -> u64 {
        let pat = format!("wire {wire} = move == 2'd");
        let at = v.find(&pat).expect("the Verilog decodes the move") + pat.len();
        v[at..at + 1].parse().unwrap()
    };
    let decoded = [code_of("hold"), code_of("lf"), code_of("dn")];
    assert_eq!(
        [Move::Hold.code(), Move::Left.code(), Move::Down.code()],
        decoded
    );
    assert!(Move::Right.code() < 4 && !decoded.contains(&Move::Right.code()));
}

/// The lane form (`kernel_batch_lanes`, what the shafts walks use) against the span
/// driver: at every chunk size of `common::BATCH_CHUNKS`, the same words, final state
/// and counters (the span's timing added once).
fn lanes_agree_with_span(u: &PolygonInterpolator, state: &PolyState, moves: &[Move]) {
    let mut s_span = state.clone();
    let mut c_span = Counters::default();
    let out_span = rtl_model::driver::run_span(u, &mut s_span, moves, &mut c_span);
    for chunk in common::BATCH_CHUNKS {
        let mut st = state.clone();
        let mut c = Counters::default();
        let mut tally = rtl_model::driver::SpanTally::new();
        let mut lanes = PolyLanes::default();
        let mut words = Vec::new();
        for part in moves.chunks(chunk.max(1)) {
            lanes.clear(u.attrs() as usize);
            assert!(lanes.is_empty(), "cleared lanes hold no word");
            u.kernel_batch_lanes(&mut st, part, &mut lanes, &mut c);
            tally.add(part.len());
            assert_eq!(lanes.len(), part.len(), "one word per move (chunk {chunk})");
            assert!(
                !lanes.is_empty(),
                "a chunk's words are held (chunk {chunk})"
            );
            words.extend((0..lanes.len()).map(|i| lanes.word(i)));
        }
        tally.close(u.timing(), &mut c);
        assert_eq!(words, out_span, "lane words differ (chunk {chunk})");
        assert_eq!(st, s_span, "lane final state differs (chunk {chunk})");
        assert_eq!(c, c_span, "lane counters differ (chunk {chunk})");
    }
    // The run-length coded form: each run whole, and each run split in two with an
    // empty entry between (a closed-form run may end part-way through a run of moves).
    let mut runs: Vec<(Move, usize)> = Vec::new();
    for &m in moves {
        match runs.last_mut() {
            Some((last, n)) if *last == m => *n += 1,
            _ => runs.push((m, 1)),
        }
    }
    let split: Vec<(Move, usize)> = runs
        .iter()
        .flat_map(|&(m, n)| [(m, n / 2), (m, 0), (m, n - n / 2)])
        .collect();
    for (name, coded) in [("whole runs", &runs), ("split runs", &split)] {
        let case = RunsCase {
            state,
            runs: coded,
            out: &out_span,
            end: &s_span,
            ctr: &c_span,
            name,
        };
        runs_agree_with_span(u, &case);
    }
}

/// Run-length coded moves `runs` from `state`, and what the span driver gives on
/// them: words `out`, final state `end` and counters `ctr` (its timing added once).
#[derive(Clone, Copy)]
struct RunsCase<'a> {
    state: &'a PolyState,
    runs: &'a [(Move, usize)],
    out: &'a [PolyOut],
    end: &'a PolyState,
    ctr: &'a Counters,
    name: &'a str,
}

/// `kernel_runs_lanes` on run-length coded moves, in one call, gives the span
/// driver's words, final state and counters.
/// Returns how many blank words were written 0 ([`runs_blank_agree`]).
fn runs_agree_with_span(u: &PolygonInterpolator, case: &RunsCase) -> usize {
    let RunsCase {
        state,
        runs,
        out,
        end,
        ctr,
        name,
    } = *case;
    let mut st = state.clone();
    let mut c = Counters::default();
    let mut lanes = PolyLanes::default();
    lanes.clear(u.attrs() as usize);
    u.kernel_runs_lanes(&mut st, runs, &mut lanes, &mut c);
    let mut tally = rtl_model::driver::SpanTally::new();
    tally.add(lanes.len());
    tally.close(u.timing(), &mut c);
    let words: Vec<PolyOut> = (0..lanes.len()).map(|i| lanes.word(i)).collect();
    assert_eq!(words, out, "run-coded lane words differ ({name})");
    assert_eq!(&st, end, "run-coded final state differs ({name})");
    assert_eq!(&c, ctr, "run-coded counters differ ({name})");
    // Lanes no consumer reads (`PolyLanes::clear_unread`): the same words with those
    // attributes 0 (their lanes empty), the same final state and counters.
    let k = u.attrs() as usize;
    for unread in [0b0101_0101u32, 0b1111, u32::MAX] {
        let mut st = state.clone();
        let mut c = Counters::default();
        let mut lanes = PolyLanes::default();
        lanes.clear_unread(k, unread);
        u.kernel_runs_lanes(&mut st, runs, &mut lanes, &mut c);
        let mut tally = rtl_model::driver::SpanTally::new();
        tally.add(lanes.len());
        tally.close(u.timing(), &mut c);
        let words: Vec<PolyOut> = (0..lanes.len()).map(|i| lanes.word(i)).collect();
        let want: Vec<PolyOut> = out
            .iter()
            .map(|o| {
                let mut o = *o;
                for (a, v) in o.attrs.iter_mut().enumerate().take(k) {
                    if (unread >> a) & 1 == 1 {
                        *v = 0;
                    }
                }
                o
            })
            .collect();
        assert_eq!(words, want, "unread {unread:#b}: words differ ({name})");
        assert_eq!(&st, end, "unread {unread:#b}: final state differs ({name})");
        assert_eq!(&c, ctr, "unread {unread:#b}: counters differ ({name})");
        for a in (0..k).filter(|&a| (unread >> a) & 1 == 1) {
            assert!(
                lanes.attrs[a].is_empty(),
                "unread lane {a} written ({name})"
            );
        }
    }
    // Covered words alone (`PolyLanes::clear_covered`), with and without unread
    // lanes: the span's covered words in order (unread attributes 0), the same final
    // state and counters (every move still stepped and counted).
    for unread in [0u32, 0b0101_0101] {
        let mut st = state.clone();
        let mut c = Counters::default();
        let mut lanes = PolyLanes::default();
        lanes.clear_covered(k, unread, true);
        u.kernel_runs_lanes(&mut st, runs, &mut lanes, &mut c);
        let mut tally = rtl_model::driver::SpanTally::new();
        tally.add(runs.iter().map(|r| r.1).sum());
        tally.close(u.timing(), &mut c);
        let words: Vec<PolyOut> = (0..lanes.len()).map(|i| lanes.word(i)).collect();
        let want: Vec<PolyOut> = out
            .iter()
            .filter(|o| o.inside)
            .map(|o| {
                let mut o = *o;
                for (a, v) in o.attrs.iter_mut().enumerate().take(k) {
                    if (unread >> a) & 1 == 1 {
                        *v = 0;
                    }
                }
                o
            })
            .collect();
        assert_eq!(
            words, want,
            "covered only, unread {unread:#b}: words differ ({name})"
        );
        assert_eq!(&st, end, "covered only: final state differs ({name})");
        assert_eq!(&c, ctr, "covered only: counters differ ({name})");
    }
    runs_blank_agree(u, case)
}

/// `kernel_runs_lanes_blank` with every other run blank in some attributes: the
/// span's words, each of a blank run's blank attributes 0 or its value (the value
/// where the run does not go in closed form), every other attribute the same; the
/// same final state and counters. A blank run in closed form writes 0 (checked by
/// the test that walks every triangle of a grid, whose runs are mostly closed form).
fn runs_blank_agree(u: &PolygonInterpolator, case: &RunsCase) -> usize {
    let RunsCase { state, runs, .. } = *case;
    let name = case.name;
    let k = u.attrs() as usize;
    let mut zeroed = 0;
    // The upper half of the attributes blank; then all, the first unread.
    let upper = ((1u32 << k) - 1) & !((1u32 << (k / 2)) - 1);
    for (mask, unread) in [(upper, 0u32), (u32::MAX, 0b1)] {
        let blank: Vec<u32> = (0..runs.len())
            .map(|i| if i % 2 == 1 { mask } else { 0 })
            .collect();
        let mut st = state.clone();
        let mut c = Counters::default();
        let mut lanes = PolyLanes::default();
        lanes.clear_unread(k, unread);
        u.kernel_runs_lanes_blank(&mut st, runs, &blank, &mut lanes, &mut c);
        let mut tally = rtl_model::driver::SpanTally::new();
        tally.add(lanes.len());
        tally.close(u.timing(), &mut c);
        assert_eq!(
            lanes.len(),
            case.out.len(),
            "blank {mask:#b}: one word per move ({name})"
        );
        let blank_words = runs
            .iter()
            .zip(&blank)
            .flat_map(|(&(_, n), &m)| std::iter::repeat_n(m, n));
        for (i, (o, m)) in case.out.iter().zip(blank_words).enumerate() {
            let w = lanes.word(i);
            assert_eq!(
                (w.x, w.y, w.inside),
                (o.x, o.y, o.inside),
                "word {i} ({name})"
            );
            for a in 0..k {
                let read = (unread >> a) & 1 == 0;
                let want = if read { o.attrs[a] } else { 0 };
                if read && (m >> a) & 1 == 1 && w.attrs[a] == 0 && want != 0 {
                    zeroed += 1;
                } else {
                    assert_eq!(
                        w.attrs[a], want,
                        "blank {mask:#b}: word {i} attribute {a} ({name})"
                    );
                }
            }
        }
        assert_eq!(
            &st, case.end,
            "blank {mask:#b}: final state differs ({name})"
        );
        assert_eq!(&c, case.ctr, "blank {mask:#b}: counters differ ({name})");
    }
    zeroed
}

// ------------------------------------------------------------ barycentric mode

/// A config with the barycentric mode: default or narrow widths, w weight bits.
fn cfg_bary(narrow: bool, k: u32, w: u32, strict: bool, q: Quant) -> PolygonInterpolator {
    let base = if narrow {
        PolygonInterpolatorConfig {
            subpixel_bits: 2,
            attr_fmt: Format {
                int_bits: 9,
                frac_bits: 0,
                signed: true,
            },
            out_int_bits: 9,
            out_frac_bits: 0,
            ..PolygonInterpolatorConfig::default()
        }
    } else {
        PolygonInterpolatorConfig::default()
    };
    PolygonInterpolatorConfig {
        attrs: k,
        out_quant: q,
        barycentric: Some(Barycentric {
            weight_bits: w,
            strict,
        }),
        ..base
    }
    .build()
    .unwrap()
}

/// The barycentric value A1 + (q0·Δ0 + q2·Δ2)/2^w has fa + w fraction bits; the
/// output rounding from there to `out_frac_bits` is the only other error.
fn bary_round_bound(u: &PolygonInterpolator, w: u32) -> f64 {
    let f = u.attr_fmt().frac_bits + w;
    let o = u.out_frac_bits();
    if o >= f {
        0.0
    } else {
        match u.out_quant() {
            Quant::Trn | Quant::TrnZero => (-(o as f64)).exp2(),
            _ => (-(o as f64 + 1.0)).exp2(),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// The barycentric mode against the twin, on random triangles (either winding):
    /// coverage exact; every covered pixel within the output rounding of
    /// `barycentric_value` (the weights' quantisation is exact in both), and within
    /// 2^−w·(|Δ0| + |Δ2|) + that rounding of the exact plane (the width-derived cost
    /// of quantising the weights).
    #[test]
    fn barycentric_triangles_match_the_twin(
        narrow in any::<bool>(),
        k in 1u32..=4,
        w in 1u32..=16,
        strict in any::<bool>(),
        q in prop::sample::select(Quant::ALL.to_vec()),
        pts in pts_strategy(3, -10.0, 60.0),
        attrs in attrs_strategy(3),
    ) {
        let u = cfg_bary(narrow, k, w, strict, q);
        let (vs, ps, ats) = quantise(&u, &pts, &attrs);
        let tri = [ps[0], ps[1], ps[2]];
        let setup = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut Counters::default());
        let mut st = setup.state.clone();
        let mut ctr = Counters::default();
        let outs = run_span(&u, &mut st, &setup.moves(), &mut ctr);
        let r = bary_round_bound(&u, w);
        let scale = (-(w as f64)).exp2();
        let s = u.subpixel_bits();
        for o in &outs {
            prop_assert_eq!(o.inside, twin::triangle_covers(tri, o.x, o.y));
            if !o.inside {
                continue;
            }
            let p = twin::centre(o.x, o.y);
            for (i, &code) in o.attrs.iter().enumerate().take(k as usize) {
                let a = [ats[0][i], ats[1][i], ats[2][i]];
                let got = u.out_to_f64(code);
                let want = clamp_out(&u, twin::barycentric_value(tri, a, p, s, w, strict));
                prop_assert!((got - want).abs() <= r + SLACK,
                    "attr {} at ({}, {}): {} vs twin {}", i, o.x, o.y, got, want);
                let plane = clamp_out(&u, twin::plane_at(tri, a, p));
                let qb = scale * ((a[0] - a[1]).abs() + (a[2] - a[1]).abs()) + r;
                prop_assert!((got - plane).abs() <= qb + SLACK,
                    "attr {} at ({}, {}): {} vs plane {} (bound {})", i, o.x, o.y, got, plane, qb);
            }
        }
    }

    /// Tick, span, batch and lane drivers agree in the barycentric mode (the fast
    /// paths step aside: every move goes through the kernel).
    #[test]
    fn barycentric_drivers_agree(
        narrow in any::<bool>(),
        k in 0u32..=4,
        w in 1u32..=16,
        strict in any::<bool>(),
        pts in pts_strategy(3, -5.0, 30.0),
        attrs in attrs_strategy(3),
        extra in prop::collection::vec(0u8..4, 0..30),
    ) {
        let u = cfg_bary(narrow, k, w, strict, Quant::Rnd);
        let mut ctr = Counters::default();
        let vs: Vec<Vertex> = (0..3)
            .map(|i| u.vertex_from_f64(i, pts[i].0, pts[i].1, &attrs[i][..k as usize], &mut ctr).unwrap())
            .collect();
        let setup = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut ctr);
        let mut moves = setup.moves();
        moves.extend(extra.iter().map(|&m| [Move::Hold, Move::Right, Move::Left, Move::Down][m as usize]));
        common::assert_drivers_agree(&u, setup.state.clone(), &moves);
        lanes_agree_with_span(&u, &setup.state, &moves);
    }
}

/// The NV2A's barycentric weights: 8 fraction bits, exact multiples kept.
const NV2A_WEIGHTS: Barycentric = Barycentric {
    weight_bits: 8,
    strict: false,
};

/// A triangle with the same attributes at its three vertices, set up and walked: the
/// walk's outputs and the counters of the walk alone (not of the setup).
fn walk_triangle(
    u: &PolygonInterpolator,
    pts: [(f64, f64); 3],
    attrs: &[f64],
) -> (Vec<PolyOut>, Counters) {
    let mut setup_ctr = Counters::default();
    let vs: Vec<Vertex> = (0..3)
        .map(|i| {
            u.vertex_from_f64(i, pts[i].0, pts[i].1, attrs, &mut setup_ctr)
                .unwrap()
        })
        .collect();
    let setup = u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut setup_ctr);
    let mut st = setup.state.clone();
    let mut ctr = Counters::default();
    let outs = run_span(u, &mut st, &setup.moves(), &mut ctr);
    (outs, ctr)
}

/// The barycentric output stage counts its events on covered pixels only: an attribute
/// of 200 everywhere saturates a 4-bit integer output at each covered pixel, one of
/// 0.25 underflows to 0 there, one of 3 does neither.
#[test]
fn barycentric_output_counts_saturations_and_underflows_on_covered_pixels() {
    let u = PolygonInterpolatorConfig {
        attrs: 3,
        out_int_bits: 4,
        out_frac_bits: 0,
        out_quant: Quant::Rnd,
        barycentric: Some(NV2A_WEIGHTS),
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap();
    let pts = [(1.0, 1.0), (17.5, 3.0), (6.0, 14.25)];
    let (outs, c) = walk_triangle(&u, pts, &[200.0, 0.25, 3.0]);
    let covered = outs.iter().filter(|o| o.inside).count() as u64;
    assert!(
        covered > 50 && (covered as usize) < outs.len(),
        "{covered} of {}",
        outs.len()
    );
    assert_eq!((c.saturations, c.underflows), (covered, covered));
}

/// The mode leaves the plane path alone: parallelograms keep their planes (no
/// barycentric registers), and weight bits outside 1 ..= 16 name the field.
#[test]
fn barycentric_mode_scope_and_errors() {
    let u = cfg_bary(false, 2, 8, true, Quant::Rnd);
    let mut ctr = Counters::default();
    let v = |i, x, y| {
        u.vertex_from_f64(i, x, y, &[1.0, 2.0], &mut Counters::default())
            .unwrap()
    };
    let p = u
        .setup_parallelogram(&[v(0, 0.0, 0.0), v(1, 8.0, 0.0), v(2, 8.0, 8.0)], &mut ctr)
        .unwrap();
    assert!(p.state.bary.is_none());
    let t = u.setup_triangle(&[v(0, 0.0, 0.0), v(1, 8.0, 0.0), v(2, 8.0, 8.0)], &mut ctr);
    assert!(t.state.bary.is_some());
    for w in [0u32, 17] {
        let e = PolygonInterpolatorConfig {
            barycentric: Some(Barycentric {
                weight_bits: w,
                strict: false,
            }),
            ..PolygonInterpolatorConfig::default()
        }
        .build()
        .unwrap_err();
        assert_eq!(e.field(), "polygon_interpolator.barycentric.weight_bits");
    }
}

/// Setup counts an underflow for each gradient and start that is non-zero but rounds
/// to 0 accumulator LSBs. Default widths: 16 attribute and 24 accumulator fraction
/// bits, so a change of one attribute LSB across 1 024 pixels is 2⁸/1 024 = 1/4
/// accumulator LSB per pixel (rounds to 0), and at the first pixel centre (½, ½) the
/// start is 1/8 LSB (rounds to 0). Each kind of attribute on its own (the counts of
/// several could cancel a wrong condition's): one growing along x only and one along
/// y only (two underflows each: the gradient and the start), a constant 5 (zero
/// gradients are not underflows) and one growing by 16 LSBs along both (gradients 4
/// LSBs, start 4 LSBs: none).
#[test]
fn setup_counts_gradients_and_starts_that_round_to_zero_as_underflows() {
    let u = cfg_default(1);
    let s = 1i64 << u.subpixel_bits();
    let v = |x: i64, y: i64, a: i64| raw_vertex(x * s, y * s, &[a]);
    // (values at (0, 0), (1024, 0), (0, 1024); underflows; dA/dx, dA/dy, start)
    for (values, underflows, state) in [
        ([0, 1, 0], 2, (0, 0, 0)),
        ([0, 0, 1], 2, (0, 0, 0)),
        ([5, 5, 5], 0, (0, 0, 5 << 8)),
        ([0, 16, 16], 0, (4, 4, 4)),
    ] {
        let tri = [
            v(0, 0, values[0]),
            v(1024, 0, values[1]),
            v(0, 1024, values[2]),
        ];
        let mut ctr = Counters::default();
        let st = u.setup_triangle(&tri, &mut ctr).state;
        assert_eq!(ctr.underflows, underflows, "{values:?}");
        assert_eq!((st.grad_x[0], st.grad_y[0], st.acc[0]), state, "{values:?}");
    }
}

/// Each accessor reads back its own field of the config the unit was built from (a
/// config whose fields all differ from the defaults and from each other).
#[test]
fn accessors_read_back_the_config() {
    let cfg = PolygonInterpolatorConfig {
        attrs: 3,
        subpixel_bits: 2,
        coord_int_bits: 11,
        attr_fmt: Format {
            int_bits: 12,
            frac_bits: 10,
            signed: false,
        },
        acc_int_bits: 17,
        acc_frac_bits: 21,
        acc_overflow: Overflow::SatSym,
        out_int_bits: 9,
        out_frac_bits: 5,
        out_quant: Quant::RndZero,
        barycentric: Some(NV2A_WEIGHTS),
    };
    let u = cfg.build().unwrap();
    assert_eq!(u.config(), cfg);
    assert_eq!(
        [
            u.attrs(),
            u.subpixel_bits(),
            u.coord_int_bits(),
            u.acc_int_bits(),
            u.acc_frac_bits(),
            u.out_int_bits(),
            u.out_frac_bits(),
        ],
        [3, 2, 11, 17, 21, 9, 5]
    );
    assert_eq!(u.attr_fmt(), cfg.attr_fmt);
    assert_eq!(u.acc_overflow(), Overflow::SatSym);
    assert_eq!(u.out_quant(), Quant::RndZero);
}

/// A run whose accumulator ends exactly on the format's minimum or maximum code, or
/// one beyond, under every overflow mode: the closed-form runs give what the per-step
/// kernel gives (SAT_SYM clamps the minimum code itself, so a run ending there must
/// not be taken as affine), and the span driver sees the clamp.
#[test]
fn runs_ending_on_the_accumulator_limits_agree_with_the_kernel() {
    for mode in Overflow::ALL {
        let u = PolygonInterpolatorConfig {
            attrs: 1,
            acc_int_bits: 4,
            acc_frac_bits: 8,
            acc_overflow: mode,
            out_frac_bits: 4,
            ..PolygonInterpolatorConfig::default()
        }
        .build()
        .unwrap();
        let acc = u.acc_fmt();
        let (lo, hi) = (acc.min_raw() as i64, acc.max_raw() as i64);
        for (start, grad) in [(lo + 3, -1), (hi - 3, 1)] {
            let mut st = PolyState::default();
            st.acc[0] = start;
            st.grad_x[0] = grad;
            for n in 1..=5 {
                let moves: Vec<Move> = std::iter::once(Move::Hold)
                    .chain(std::iter::repeat_n(Move::Right, n))
                    .collect();
                common::assert_drivers_agree(&u, st.clone(), &moves);
                lanes_agree_with_span(&u, &st, &moves);
                let mut end = st.clone();
                let mut c = Counters::default();
                run_span(&u, &mut end, &moves, &mut c);
                let clamped = mode == Overflow::SatSym && grad < 0 && n >= 3;
                assert_eq!(
                    c.saturations > 0,
                    clamped || (mode != Overflow::Wrap && n > 3),
                    "{mode:?} from {start} by {grad}, {n} steps"
                );
            }
        }
    }
}

/// A hand-loaded state whose first edge function wraps at its width (2c + 2s + 4 bits)
/// part-way through a run, in either direction: the closed-form runs give what the
/// per-step kernel gives (the wrapped edge is negative: the pixels after it are
/// outside), and the kernel counts the wrap. Setup never loads such a state (every
/// pixel centre of the coordinate range has edges well inside the width); the
/// registers' behaviour is defined for any state.
#[test]
fn runs_whose_edge_wraps_agree_with_the_kernel() {
    let u = cfg_default(1);
    let top = (1i64 << (u.edge_bits() - 1)) - 1;
    for (edge, step) in [(top - 2, 1), (-top + 1, -1)] {
        let mut st = PolyState::default();
        st.edge[0] = edge;
        st.edge_dx[0] = step;
        st.grad_x[0] = 5;
        let moves: Vec<Move> = std::iter::once(Move::Hold)
            .chain(std::iter::repeat_n(Move::Right, 5))
            .collect();
        let outs = common::assert_drivers_agree(&u, st.clone(), &moves);
        lanes_agree_with_span(&u, &st, &moves);
        let mut c = Counters::default();
        run_span(&u, &mut st.clone(), &moves, &mut c);
        assert_eq!(c.overflows, 1, "one wrap of one edge");
        let inside: Vec<bool> = outs.iter().map(|o| o.inside).collect();
        let want = if step > 0 {
            [true, true, true, false, false, false]
        } else {
            [false, false, false, true, true, true]
        };
        assert_eq!(inside, want, "edge {edge} stepping {step}");
    }
}

/// The pixel counters are `coord_int_bits` wide and wrap (each wrap counted once): x
/// stepping right past its largest value, y stepping down past its, and x stepping
/// left past its smallest, each with the other counter in range.
#[test]
fn pixel_counters_wrap_at_their_width_each_wrap_counted() {
    let u = cfg_default(1);
    let half = 1i64 << (u.coord_int_bits() - 1);
    for (x, y, mv, end) in [
        (half - 2, 7, Move::Right, (-half, 7)),
        (7, half - 2, Move::Down, (7, -half)),
        (-half + 1, 7, Move::Left, (half - 1, 7)),
    ] {
        let st = PolyState {
            x,
            y,
            ..PolyState::default()
        };
        let moves = [Move::Hold, mv, mv];
        let outs = common::assert_drivers_agree(&u, st.clone(), &moves);
        lanes_agree_with_span(&u, &st, &moves);
        assert_eq!((outs[2].x, outs[2].y), end, "{mv:?} from ({x}, {y})");
        let mut c = Counters::default();
        run_span(&u, &mut st.clone(), &moves, &mut c);
        assert_eq!(c.overflows, 1, "{mv:?} from ({x}, {y})");
    }
}

/// Setup loads the barycentric registers only in the barycentric mode and only for a
/// triangle that covers a pixel centre: the planes' configs and an empty triangle
/// leave them unloaded.
#[test]
fn barycentric_registers_load_only_in_the_mode_for_a_covering_triangle() {
    let s = 1i64 << PolygonInterpolatorConfig::default().subpixel_bits;
    let v = |x: i64, y: i64| raw_vertex(x, y, &[3, 3]);
    let big = [v(0, 0), v(40 * s, 0), v(0, 40 * s)];
    // Between pixel centres: x and y within (0.5, 1.5) pixels' first sub-pixels.
    let sliver = [v(s, s), v(s + 2, s), v(s, s + 2)];
    let planes = cfg_default(2);
    let bary = cfg_bary(false, 2, 8, true, Quant::Rnd);
    let mut ctr = Counters::default();
    assert!(planes.setup_triangle(&big, &mut ctr).state.bary.is_none());
    assert!(bary.setup_triangle(&big, &mut ctr).state.bary.is_some());
    let empty = bary.setup_triangle(&sliver, &mut ctr);
    assert!(empty.bbox.is_none() && empty.state.bary.is_none());
}

/// Unsigned attribute words are masked to their width: bits above it are dropped, the
/// bits within kept (a constant 8-bit colour of 200 given with junk above bit 7 starts
/// every accumulator at 200).
#[test]
fn unsigned_attribute_words_are_masked_to_their_width() {
    let u = PolygonInterpolatorConfig {
        attrs: 2,
        attr_fmt: Format {
            int_bits: 8,
            frac_bits: 0,
            signed: false,
        },
        out_int_bits: 8,
        out_frac_bits: 0,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap();
    let s = 1i64 << u.subpixel_bits();
    let v = |x: i64, y: i64| raw_vertex(x, y, &[200, 200 + (5 << 8)]);
    let setup = u.setup_triangle(
        &[v(0, 0), v(30 * s, 0), v(0, 30 * s)],
        &mut Counters::default(),
    );
    let start = 200i64 << u.acc_frac_bits();
    assert_eq!(setup.state.acc[..2], [start, start]);
    let mut st = setup.state.clone();
    let outs = run_span(&u, &mut st, &setup.moves(), &mut Counters::default());
    assert!(outs
        .iter()
        .filter(|o| o.inside)
        .all(|o| o.attrs[..2] == [200, 200]));
}

/// The barycentric mode's part of the cost: two dividers (edge over area: one bit
/// wider than an edge, w + 1 quotient bits) and per attribute two (w + 1) × (attr + 1)
/// multipliers, two adders of attr + w + 3 bits and the base and delta registers
/// (attr + 2·(attr + 1) bits); the planes' configs have none.
#[test]
fn barycentric_mode_prices_its_dividers_and_per_attribute_datapath() {
    use rtl_model::cost::prim;
    const PART: &str = "barycentric weights: 2 dividers (edge/area, w + 1 quotient bits), per attribute 2 multipliers (w+1)×(attr+1), 2 adders, base and delta registers";
    let part = |u: &PolygonInterpolator| {
        common::cost_part(&u.cost(), PART).unwrap_or_else(|| panic!("no part {PART}"))
    };
    assert_eq!(part(&cfg_default(4)), 0.0);
    for (k, w, attr_int, attr_frac) in [(1u32, 8u32, 8u32, 0u32), (3, 4, 16, 16), (4, 12, 9, 3)] {
        let u = PolygonInterpolatorConfig {
            attrs: k,
            attr_fmt: s_fmt(attr_int, attr_frac),
            barycentric: Some(Barycentric {
                weight_bits: w,
                strict: true,
            }),
            ..PolygonInterpolatorConfig::default()
        }
        .build()
        .unwrap();
        let a = attr_int + attr_frac;
        let per_attr = prim::multiplier(w + 1, a + 1) * 2.0
            + prim::adder(a + w + 3) * 2.0
            + prim::register(a + 2 * (a + 1));
        let want = prim::divider(u.edge_bits() + 1, w + 1) * 2.0 + per_attr * k as f64;
        assert_eq!(part(&u), want.nand2_eq(), "k {k} w {w} attr {a} b");
    }
}

/// The VCD trace's wires: the 2-bit move in; out the pixel counters at
/// `coord_int_bits`, the inside bit and each attribute at the output width, every
/// code masked to its wire (negative values as two's complement).
#[test]
fn trace_signals_are_the_move_and_the_outputs_masked_to_their_widths() {
    let u = PolygonInterpolatorConfig {
        attrs: 2,
        out_int_bits: 10,
        out_frac_bits: 6,
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap();
    assert_eq!(
        common::wires(&u.in_signals(&Move::Down)),
        [("move", 2, Move::Down.code())]
    );
    let mut attrs = [0; MAX_ATTRS];
    attrs[..3].copy_from_slice(&[-1, 0x1_2345, 77]);
    let o = PolyOut {
        x: -2,
        y: 0x3_0005,
        inside: true,
        attrs,
    };
    let c = u.coord_int_bits();
    let cm = (1u64 << c) - 1;
    assert_eq!(
        common::wires(&u.out_signals(&o)),
        [
            ("x", c, cm - 1),
            ("y", c, 0x3_0005 & cm),
            ("inside", 1, 1),
            ("attr0", 16, 0xffff),
            ("attr1", 16, 0x2345),
        ]
    );
}

/// `PolyLanes::reserve`: room for n more words in x, y, inside and every written
/// attribute lane, and none taken for the lanes left unread (nor past `k`).
#[test]
fn reserve_makes_room_in_the_written_lanes_only() {
    let mut lanes = PolyLanes::default();
    // Attributes 0..5 of which 1 and 3 are unread.
    lanes.clear_unread(5, 0b01010);
    lanes.reserve(100);
    assert!(lanes.x.capacity() >= 100 && lanes.y.capacity() >= 100);
    assert!(lanes.inside.capacity() >= 100);
    for (a, l) in lanes.attrs.iter().enumerate() {
        let written = a < 5 && a != 1 && a != 3;
        assert_eq!(l.capacity() >= 100, written, "attribute {a}'s lane");
        if !written {
            assert_eq!(l.capacity(), 0, "attribute {a}'s lane took room");
        }
    }
}

/// Events counted on runs whose accumulator moves by a few LSBs a step: runs that
/// reach the zero code, step onto an accumulator of exactly 0 (rounds to 0: no
/// underflow), and enter or leave the output range part-way, rising and falling,
/// with the covered steps a part of each run (an edge leaves the primitive
/// part-way). In every rounding mode the lane forms (read, unread, covered only)
/// give the drivers' words, final state and counters; each kind of event occurs.
#[test]
fn events_of_runs_of_small_steps_agree_with_the_drivers() {
    let (mut under, mut sat) = (0, 0);
    for q in Quant::ALL {
        let u = narrow_out(
            PolygonInterpolatorConfig {
                attrs: MAX_ATTRS as u32,
                ..PolygonInterpolatorConfig::default()
            },
            q,
        );
        let sh = u.acc_fmt().frac_bits - u.out_fmt().frac_bits;
        let (half, top) = (1i64 << (sh - 1), (u.out_fmt().max_raw() as i64) << sh);
        let bottom = u.out_fmt().min_raw() as i64 * (1i64 << sh);
        // (first accumulator value, step): into the zero code and out of it, through an
        // accumulator of exactly 0, up out of the range and down out of it.
        let lines = [
            (-half - 5, 1),
            (half + 5, -1),
            (-3, 1),
            (6, -2),
            (top + half - 5, 1),
            (bottom - half + 5, -1),
            (-half - 40, 3),
            (top - 7, 7),
        ];
        let mut st = PolyState {
            x: 0,
            y: 0,
            edge: [14, 1 << 20, 1 << 20, 1 << 20],
            edge_dx: [-1, 0, 0, 0],
            edge_dy: [0; 4],
            acc: [0; MAX_ATTRS],
            grad_x: [0; MAX_ATTRS],
            grad_y: [0; MAX_ATTRS],
            bary: None,
        };
        for (a, &(a0, g)) in lines.iter().enumerate() {
            st.acc[a] = a0;
            st.grad_x[a] = g;
            st.grad_y[a] = -g;
        }
        let mut moves = vec![Move::Hold];
        for row in 0..4 {
            let dir = if row % 2 == 0 {
                Move::Right
            } else {
                Move::Left
            };
            moves.extend(std::iter::repeat_n(dir, 30));
            moves.push(Move::Down);
        }
        let mut c = Counters::default();
        run_span(&u, &mut st.clone(), &moves, &mut c);
        under += c.underflows;
        sat += c.saturations;
        common::assert_drivers_agree(&u, st.clone(), &moves);
        lanes_agree_with_span(&u, &st, &moves);
    }
    assert!(under > 0, "some run must reach the zero code");
    assert!(sat > 0, "some run must leave the output range");
}

/// `attr_code_range` on parallelograms and triangles: where it answers, the least
/// and greatest code of the attribute over the rectangle's pixels as the walk
/// writes them (covered or not); it answers on most of them (the accumulators stay
/// in range) and never for the barycentric mode. `attr_row` along the rectangle's
/// top row: each pixel's code as the walk writes it.
#[test]
fn attr_code_range_is_the_walks_least_and_greatest_code() {
    let mut rng = <rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(7);
    let (mut answered, mut rows_answered) = (0, 0);
    let cases = 200;
    for case in 0..cases {
        use rand::Rng;
        let u = config_by_index(case % 3, MAX_ATTRS as u32);
        let pts: Vec<(f64, f64)> = (0..3)
            .map(|_| (rng.random_range(2.0..40.0), rng.random_range(2.0..40.0)))
            .collect();
        let attrs: Vec<Vec<f64>> = (0..3)
            .map(|_| {
                (0..MAX_ATTRS)
                    .map(|_| rng.random_range(-100.0..100.0))
                    .collect()
            })
            .collect();
        let (vs, _, _) = quantise(&u, &pts, &attrs);
        let mut ctr = Counters::default();
        let setup = if case % 2 == 0 {
            u.setup_parallelogram(&[vs[0], vs[1], vs[2]], &mut ctr)
                .unwrap()
        } else {
            u.setup_triangle(&[vs[0], vs[1], vs[2]], &mut ctr)
        };
        let Some(b) = setup.bbox else { continue };
        let outs = run_span(&u, &mut setup.state.clone(), &setup.moves(), &mut ctr);
        let (x0, x1) = sorted(rng.random_range(b.x0..=b.x1), rng.random_range(b.x0..=b.x1));
        let (y0, y1) = sorted(rng.random_range(b.y0..=b.y1), rng.random_range(b.y0..=b.y1));
        for a in 0..MAX_ATTRS {
            let codes = outs
                .iter()
                .filter(|o| (x0..=x1).contains(&o.x) && (y0..=y1).contains(&o.y))
                .map(|o| o.attrs[a]);
            let want = (codes.clone().min().unwrap(), codes.max().unwrap());
            if let Some(got) = u.attr_code_range(&setup, a, x0..=x1, y0..=y1) {
                assert_eq!(
                    got, want,
                    "case {case} attribute {a}: rectangle {x0}..={x1} × {y0}..={y1}"
                );
                answered += 1;
            }
            // Along row y0 alone, each pixel's code.
            if let Some(line) = u.attr_row(&setup, a, x0..=x1, y0) {
                let row = outs
                    .iter()
                    .filter(|o| o.y == y0 && (x0..=x1).contains(&o.x));
                for o in row {
                    let at = format!("case {case} attribute {a}: pixel ({}, {y0})", o.x);
                    assert_eq!(line.code(o.x), o.attrs[a], "{at}");
                }
                rows_answered += 1;
            }
        }
        assert_eq!(u.attr_code_range(&setup, MAX_ATTRS, x0..=x1, y0..=y1), None);
        assert_eq!(u.attr_row(&setup, MAX_ATTRS, x0..=x1, y0), None);
    }
    assert!(
        answered > cases * MAX_ATTRS / 2,
        "answered {answered} of {}",
        cases * MAX_ATTRS
    );
    assert!(
        rows_answered >= answered,
        "a row answers where its rectangle does: {rows_answered} rows, {answered} rectangles"
    );
    // The barycentric mode's codes are not affine in the pixel: no answer.
    let u = PolygonInterpolatorConfig {
        barycentric: Some(Barycentric {
            weight_bits: 8,
            strict: false,
        }),
        ..PolygonInterpolatorConfig::default()
    }
    .build()
    .unwrap();
    let v = |x: f64, y: f64| {
        u.vertex_from_f64(0, x, y, &[1.0, 2.0, 3.0, 4.0], &mut Counters::default())
            .unwrap()
    };
    let s = u.setup_triangle(
        &[v(1.0, 1.0), v(20.0, 2.0), v(3.0, 18.0)],
        &mut Counters::default(),
    );
    assert!(
        s.state.bary.is_some(),
        "the barycentric mode's setup loads its registers"
    );
    assert_eq!(u.attr_code_range(&s, 0, 2..=5, 2..=5), None);
    assert_eq!(u.attr_row(&s, 0, 2..=5, 2), None);
}

fn sorted(a: i64, b: i64) -> (i64, i64) {
    (a.min(b), a.max(b))
}

/// The host walks' case: a parallelogram over about 60 × 42 pixels whose vertex i's
/// attribute a is i·ki + a·ka − off, and `walk_rows_lanes`'s words and counters on it.
fn host_walk_case(
    u: &PolygonInterpolator,
    (ki, ka, off): (usize, usize, usize),
) -> (PolySetup, Vec<PolyOut>, Counters) {
    use glare_pipeline::pipeline::raster::{walk_rows_lanes, WalkBuffers};
    let pts = [(1.5, 2.0), (61.0, 3.5), (58.0, 44.0)];
    let attrs: Vec<Vec<f64>> = (0..3)
        .map(|i| {
            (0..MAX_ATTRS)
                .map(|a| (i * ki + a * ka) as f64 - off as f64)
                .collect()
        })
        .collect();
    let (vs, _, _) = quantise(u, &pts, &attrs);
    let s = u
        .setup_parallelogram(&[vs[0], vs[1], vs[2]], &mut Counters::default())
        .unwrap();
    let (mut want, mut c_want) = (Vec::new(), Counters::default());
    walk_rows_lanes(u, &s, &mut c_want, &mut WalkBuffers::default(), |l| {
        want.extend((0..l.len()).map(|i| l.word(i)));
    });
    (s, want, c_want)
}

/// The host's walk in chunks of rows of one kind (`walk_rows_lanes_by`): the same
/// words in order as `walk_rows_lanes` (a kind's unread attributes left empty), each
/// chunk's rows of one kind, and the same counters.
#[test]
fn a_walk_by_row_kinds_gives_the_walks_words_and_counters() {
    use glare_pipeline::pipeline::raster::{walk_rows_lanes_by, WalkBuffers};
    let u = cfg_default(MAX_ATTRS as u32);
    let (s, want, c_want) = host_walk_case(&u, (7, 3, 9));
    let unread = 0b1111_0000u32;
    let kind = |row: u64| row % 5 < 2;
    let b = s.bbox.unwrap();
    let (mut got, mut c_got, mut chunks) = (Vec::new(), Counters::default(), 0);
    let by_kind = |row: u64| (if kind(row) { unread } else { 0 }, kind(row));
    walk_rows_lanes_by(
        &u,
        &s,
        &mut c_got,
        &mut WalkBuffers::default(),
        by_kind,
        |l, k| {
            chunks += 1;
            assert!(
                l.y.iter().all(|&y| kind((y - b.y0) as u64) == k),
                "a chunk of one kind"
            );
            for a in 0..MAX_ATTRS {
                assert_eq!(l.is_read(a), !k || (unread >> a) & 1 == 0);
            }
            got.extend((0..l.len()).map(|i| (l.word(i), k)));
        },
    );
    assert!(
        chunks >= 16,
        "the kind changes every few rows: {chunks} chunks"
    );
    assert_eq!(got.len(), want.len());
    for ((g, k), w) in got.iter().zip(&want) {
        let mut w = *w;
        if *k {
            w.attrs[4..8].fill(0);
        }
        assert_eq!(*g, w);
    }
    assert_eq!(c_got, c_want);
}

/// The host's walk with blank stretches (`walk_rows_lanes_blank`): the same words as
/// `walk_rows_lanes`, in order, each chunk's rows of one kind; each stretch handed to
/// the sink is the words of one row's blank columns (with its label), exactly; the
/// blank attributes of those words 0 or their value, every other one the same; the
/// same counters.
#[test]
fn a_walk_with_blank_stretches_gives_the_walks_words_and_counters() {
    use glare_pipeline::pipeline::raster::{walk_rows_lanes_blank, WalkBuffers};
    let u = cfg_default(MAX_ATTRS as u32);
    let (s, want, c_want) = host_walk_case(&u, (5, 4, 11));
    let b = s.bbox.unwrap();
    let blank = 0b1111_0000u32;
    // Rows 0, 3, 6, …: a stretch near each end (the right one past the box, clipped);
    // rows 1, 4, …: one in the middle; others none. The kind changes every 5 rows.
    let blanks = |row: u64| match row % 3 {
        0 => [
            Some((b.x0 + 3..=b.x0 + 10, row * 2)),
            Some((b.x1 - 7..=b.x1 + 4, row * 2 + 1)),
        ],
        1 => [Some((b.x0 + 20..=b.x0 + 25, row * 2)), None],
        _ => [None, None],
    };
    let kind = |row: u64| (0, row % 5 < 2, blanks(row));
    let (mut got, mut c_got) = (Vec::new(), Counters::default());
    let mut in_stretch = Vec::new();
    let mut stretches = 0;
    walk_rows_lanes_blank(
        &u,
        &s,
        &mut c_got,
        &mut WalkBuffers::default(),
        blank,
        kind,
        |l, k, st: &[(std::ops::Range<usize>, u64)]| {
            let base = got.len();
            assert!(
                l.y.iter().all(|&y| ((y - b.y0) as u64 % 5 < 2) == k),
                "one kind"
            );
            got.extend((0..l.len()).map(|i| l.word(i)));
            in_stretch.resize(got.len(), false);
            for (words, label) in st {
                stretches += 1;
                let row = (l.y[words.start] - b.y0) as u64;
                let side = (label - row * 2) as usize;
                let (cols, _) = blanks(row)[side].clone().unwrap();
                let cols = (*cols.start()).max(b.x0)..=(*cols.end()).min(b.x1);
                assert_eq!(
                    words.len() as i64,
                    cols.end() - cols.start() + 1,
                    "row {row}"
                );
                for i in words.clone() {
                    assert!(cols.contains(&l.x[i]) && l.y[i] == row as i64 + b.y0);
                    in_stretch[base + i] = true;
                }
            }
        },
    );
    let rows = b.height();
    let expected = (0..rows)
        .map(|r| blanks(r).iter().flatten().count())
        .sum::<usize>();
    assert_eq!(stretches, expected, "every stretch handed over once");
    assert_eq!(got.len(), want.len());
    let mut zeroed = 0;
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert_eq!((g.x, g.y, g.inside), (w.x, w.y, w.inside), "word {i}");
        for a in 0..MAX_ATTRS {
            let blanked = in_stretch[i] && (blank >> a) & 1 == 1;
            zeroed += usize::from(blanked && g.attrs[a] == 0 && w.attrs[a] != 0);
            assert!(
                g.attrs[a] == w.attrs[a] || (blanked && g.attrs[a] == 0),
                "word {i} attribute {a}: {} for {}",
                g.attrs[a],
                w.attrs[a]
            );
        }
        // A word whose column lies in its row's blank columns is in a stretch.
        let row = (g.y - b.y0) as u64;
        let listed = blanks(row).iter().flatten().any(|(c, _)| c.contains(&g.x));
        assert_eq!(in_stretch[i], listed, "word {i} at ({}, {})", g.x, g.y);
    }
    // (The rows go in closed form: their blank words hold 0.)
    assert!(zeroed > 100, "blank words written 0: {zeroed}");
    assert_eq!(c_got, c_want);
}
