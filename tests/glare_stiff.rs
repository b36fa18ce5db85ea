//! Stiff and extreme cases of the glare pipeline (issue 4): θ → 0 with θ₀ → 0 in
//! eq. (1), m = 8, intensity 0, 10⁶ and 10⁹, zero-size sources, an elliptic source
//! with a = b, directivity perpendicular to the view (c_D = 0), sources larger than
//! or beyond the coordinate range, the chaos map with z → 1, z → 2 and a near 0 or 1,
//! and the f64 reference functions at extreme arguments.
//!
//! Each case renders the bit-accurate frame on a small image (160 × 120 or 96 × 64;
//! the built-ins' sources are 20 units away, so at 160 × 120 one degree is 4.7
//! pixels) and the f64 reference image of the same sources, and asserts: no panic,
//! no NaN (reference finite, every level in [0, 255]), and the bound stated in the
//! test's doc comment (these doc comments are the documented behaviours, collected in
//! docs/glare.md § Stiff and extreme cases).
//!
//! The general bound against the reference, where a case states no tighter one:
//! RMS ≤ 2.5 levels (1 % of full scale) and mean |Δ| ≤ 1 level over the frame. The
//! built-ins measure RMS 0.4 … 1.1 at this size; the error is the shape and falloff
//! RAMs' interpolation at the bloom's steep core and the lines' ends, plus the half-
//! LSB cut-off of each profile.

use glare_pipeline::pipeline::glare::cli::{reference_levels, render_and_predict};
use glare_pipeline::pipeline::glare::fluctuation::chaos_unit;
use glare_pipeline::pipeline::glare::frame::{fit_area, line_fits, GlareFrame, COORD_LIMIT_PX};
use glare_pipeline::pipeline::glare::host::{px_per_deg, screen_sources, source_glare};
use glare_pipeline::pipeline::glare::tables::AreaPrim;
use glare_pipeline::pipeline::shafts::view::CameraView;
use glare_pipeline::reference::glare_model::{
    bloom_extended, bloom_point, ellipse_distance, flare_line_at, flare_profile, halo,
    polygon_distance, reference_image, Bloom, FlareLine, Shape2D,
};
use glare_pipeline::report::metrics::{error_stats, ErrorStats};
use glare_pipeline::scene::builtin_glare::glare_builtin;
use glare_pipeline::scene::format::Scene;
use glare_pipeline::scene::glare::{Determinants, GlareModel, GlareSection, SourceKind};
use proptest::prelude::*;

// ---------------------------------------------------------------- helpers

const RMS_TOL: f64 = 2.5;
const MEAN_TOL: f64 = 1.0;

/// A built-in glare scene at `w` × `h`.
fn small(name: &str, w: u32, h: u32) -> Scene {
    let mut s = glare_builtin(name).unwrap();
    s.image.width = w;
    s.image.height = h;
    s
}

fn glare(s: &mut Scene) -> &mut GlareSection {
    s.glare.as_mut().unwrap()
}

struct Run {
    frame: GlareFrame,
    reference: Vec<[f64; 3]>,
    stats: ErrorStats,
}

/// Validate, render, build the reference; assert no NaN anywhere and every level in
/// [0, 255] on both sides.
fn run(tag: &str, s: &Scene) -> Run {
    s.validate()
        .unwrap_or_else(|e| panic!("{tag}: invalid scene: {e}"));
    let (frame, _, _) = render_and_predict(s).unwrap_or_else(|e| panic!("{tag}: {e}"));
    let reference = reference_levels(s, &frame).unwrap();
    for (k, p) in reference.iter().enumerate() {
        for v in p {
            assert!(
                v.is_finite() && (0.0..=255.0).contains(v),
                "{tag}: reference pixel {k} = {v}"
            );
        }
    }
    for (k, p) in frame.levels().iter().enumerate() {
        for v in p {
            assert!((0.0..=255.0).contains(v), "{tag}: frame pixel {k} = {v}");
        }
    }
    let stats = error_stats(&frame.levels(), &reference).unwrap();
    println!(
        "{tag}: {} primitives, mean |Δ| {:.3}, RMS {:.3}, max {:.1} levels",
        frame.prims.len(),
        stats.mean_abs,
        stats.rms,
        stats.max
    );
    Run {
        frame,
        reference,
        stats,
    }
}

fn assert_bounded(tag: &str, r: &Run) {
    assert!(
        r.stats.rms <= RMS_TOL && r.stats.mean_abs <= MEAN_TOL,
        "{tag}: RMS {:.3} mean {:.3}",
        r.stats.rms,
        r.stats.mean_abs
    );
}

/// RGB codes of the framebuffer (alpha dropped).
fn rgb(f: &GlareFrame) -> Vec<[u32; 3]> {
    f.fb.data.chunks(4).map(|p| [p[0], p[1], p[2]]).collect()
}

fn saturations(f: &GlareFrame, unit: &str) -> u64 {
    f.counters.get(unit).map_or(0, |c| c.saturations)
}

fn left_out(f: &GlareFrame, unit: &str) -> bool {
    f.elaboration
        .iter()
        .find(|e| e.name == unit)
        .unwrap_or_else(|| panic!("no elaboration row for {unit}"))
        .left_out
        .is_some()
}

/// Level of the pixel holding screen point `c`.
fn level_at(f: &GlareFrame, c: [f64; 2]) -> [f64; 3] {
    let (x, y) = (c[0].floor() as u32, c[1].floor() as u32);
    f.levels()[(y * f.fb.width + x) as usize]
}

// ---------------------------------------------------------------- eq. (1) stiff

/// θ → 0 with θ₀ → 0 in eq. (1), m = 8 (point source, `point_theta0_deg` = 10⁻⁹
/// and 10⁻³⁰⁰, `point_m` = 8): the profile is a spike A/θ⁸. Behaviour: no NaN, the
/// f64 value at the centre is huge but finite (A/θ₀⁸, capped at f64::MAX when θ₀⁸
/// underflows), the falloff RAM holds the profile over the modulator's gain (its
/// largest, ~4095 codes), the centre pixel saturates at 255 (counted by the
/// combiner), the lit area is small (A/θ⁸ ≥ ½ for θ ≤ (2A)^(1/8) ≈ 2.5°, so the
/// bloom's quad is ≤ 26 × 26 pixels at 4.7 px/°) and the error against the
/// reference stays within the general bound.
#[test]
fn point_theta0_to_zero_m8() {
    for theta0 in [1e-9, 1e-300] {
        let mut s = small("glare-point", 160, 120);
        glare(&mut s).model.point_theta0_deg = theta0;
        glare(&mut s).model.point_m = 8.0;
        let tag = format!("point θ₀ = {theta0:e}, m = 8");
        let r = run(&tag, &s);
        assert_bounded(&tag, &r);
        let src = &r.frame.sources[0];
        let Some(Bloom::Point { a, theta0: t0, m }) = src.bloom else {
            panic!("{tag}: no point bloom");
        };
        assert_eq!((t0, m), (theta0, 8.0));
        let peak = bloom_point(0.0, a, t0, m);
        assert!(peak.is_finite() && peak > 1e60, "{tag}: peak {peak}");
        assert_eq!(level_at(&r.frame, src.center), [255.0; 3], "{tag}");
        assert!(saturations(&r.frame, "glare_combiner") > 0, "{tag}");
        let bloom = r.frame.prims.iter().find(|p| p.kind == "bloom").unwrap();
        assert!(bloom.walked <= 26 * 26, "{tag}: {bloom:?}");
    }
}

/// m = 8 for extended sources (`bloom_m` = 8, the glare-flare elliptic with its
/// lines and a halo): the tail B/(θ + θ₁)⁸ dies within ~1.5° of the rim. Behaviour:
/// finite, within the general bound.
#[test]
fn extended_m8() {
    let mut s = small("glare-flare", 160, 120);
    glare(&mut s).model.bloom_m = 8.0;
    glare(&mut s).sources[0].halo = true;
    let r = run("elliptic bloom_m = 8", &s);
    assert_bounded("elliptic bloom_m = 8", &r);
}

// ---------------------------------------------------------------- intensity

/// Intensity 0 (also at `e_intensity` = 0, where I^e = 0⁰ = 1, and a fluctuating
/// patch at S = 0 is the same case): nothing is drawn. Behaviour: the framebuffer
/// equals the background exactly, the source has no bloom, halo or flare, no
/// primitive is set up, and the elaboration leaves every glare unit out (each row
/// with its reason and the gates it saves > 0).
#[test]
fn intensity_zero_is_the_background() {
    for e_int in [0.5, 0.0] {
        let mut s = small("glare-flare", 160, 120);
        let g = glare(&mut s);
        g.sources[0].intensity = 0.0;
        g.sources[0].halo = true;
        g.model.e_intensity = e_int;
        let tag = format!("intensity 0, e_intensity {e_int}");
        let r = run(&tag, &s);
        assert_eq!(rgb(&r.frame), r.frame.base, "{tag}");
        assert_eq!(r.stats.max, 0.0, "{tag}");
        let src = &r.frame.sources[0];
        assert!(src.bloom.is_none() && src.halo.is_none() && src.flare.is_none());
        assert!(r.frame.prims.is_empty());
        assert!(r.frame.units.is_empty(), "{tag}: {:?}", r.frame.units);
        for e in &r.frame.elaboration {
            assert!(e.left_out.is_some(), "{tag}: {} elaborated", e.name);
            assert!(e.gates_saved > 0.0, "{tag}: {} saves nothing", e.name);
        }
    }
}

/// Intensity 10⁶ and 10⁹ (the validation's largest): the core and most of the frame
/// saturate. Behaviour: the centre pixel is 255 in every channel, the combiner and
/// the modulator count saturations (the modulator's gain clamps at its u12.4
/// maximum), the bloom's quad is clamped to the viewport (walked ≤ w·h) and the
/// flare lines to `flare_max_lines` (64), and the error against the reference stays
/// within the general bound (both sides saturate).
#[test]
fn intensity_huge_saturates() {
    for i in [1e6, 1e9] {
        let mut s = small("glare-flare", 160, 120);
        glare(&mut s).sources[0].intensity = i;
        glare(&mut s).sources[0].halo = true;
        let tag = format!("intensity {i:e}");
        let r = run(&tag, &s);
        assert_bounded(&tag, &r);
        let src = &r.frame.sources[0];
        assert_eq!(level_at(&r.frame, src.center), [255.0; 3], "{tag}");
        assert!(saturations(&r.frame, "glare_combiner") > 0, "{tag}");
        assert!(saturations(&r.frame, "bloom_flare_modulator") > 0, "{tag}");
        for p in &r.frame.prims {
            assert!(p.walked <= 160 * 120, "{tag}: {p:?}");
        }
        assert_eq!(src.flare.unwrap().num, 64, "{tag}");
        assert_eq!(r.frame.lines[0].len(), 64, "{tag}");
        // More than half the frame is at full scale in green.
        let full = r.frame.levels().iter().filter(|p| p[1] >= 255.0).count();
        assert!(full > 160 * 120 / 2, "{tag}: {full} saturated pixels");
    }
}

// ---------------------------------------------------------------- zero size

/// Zero-size sources: a circle with a = 0, an ellipse and a cylinder with
/// a = b = 0, and a polygon whose vertices all coincide with P₀ are all the point
/// at P₀ on screen. Behaviour: the distance to the outline is the distance to P₀
/// for all four; with flare lines off their frames are byte-identical (bloom with
/// the extended profile A·exp(−(θ/w)ⁿ) + B/(θ+θ₁)^m from the centre, and the halo);
/// only the core saturates (< 5 % of the frame; the coincident polygon once filled
/// all of it: every point passed its inside test); within the general bound. With lines on, circle and polygon draw the same lines (R(N) = 0) and
/// ellipse and cylinder the same lines (R(N) = the degenerate major axis + π/2).
#[test]
fn zero_size_sources_are_points() {
    let variant = |kind: SourceKind, flare: bool| {
        let mut s = small("glare-flare", 160, 120);
        let g = glare(&mut s);
        let src = &mut g.sources[0];
        src.kind = kind;
        src.a = 0.0;
        src.b = 0.0;
        src.halo = true;
        src.flare = flare;
        if kind == SourceKind::Polygon {
            src.vertices = vec![src.position; 3];
        }
        s
    };
    let kinds = [
        SourceKind::Circle,
        SourceKind::Elliptic,
        SourceKind::Cylindrical,
        SourceKind::Polygon,
    ];
    let mut images = Vec::new();
    for kind in kinds {
        let tag = format!("{kind:?} of zero size");
        let r = run(&tag, &variant(kind, false));
        assert_bounded(&tag, &r);
        let src = &r.frame.sources[0];
        assert_eq!(src.shape.extent(), 0.0, "{tag}");
        for (dx, dy) in [(0.0, 0.0), (3.0, 4.0), (-7.5, 1.0)] {
            let d = src.shape.distance(dx, dy);
            assert!((d - f64::hypot(dx, dy)).abs() < 1e-9, "{tag}: {d}");
        }
        let lv = r.frame.levels();
        let full = lv.iter().filter(|p| p[1] >= 255.0).count();
        assert!(full < 160 * 120 / 20, "{tag}: {full} saturated pixels");
        images.push(rgb(&r.frame));
    }
    for (k, im) in images.iter().enumerate().skip(1) {
        assert!(im == &images[0], "{:?} differs from the circle", kinds[k]);
    }
    // With lines: circle = polygon, ellipse = cylinder.
    let with: Vec<_> = kinds
        .iter()
        .map(|&k| rgb(&run(&format!("{k:?} zero, lines"), &variant(k, true)).frame))
        .collect();
    assert!(with[0] == with[3], "circle and polygon lines differ");
    assert!(with[1] == with[2], "ellipse and cylinder lines differ");
}

/// The elliptic source with a = b is a circle: its outline on screen is the circle
/// of the same radius (to 10⁻⁹ px), so with lines off (their base direction R(N)
/// is the numerically arbitrary major axis for a = b) its frame equals the circle
/// source's to within 1 level. Within the general bound.
#[test]
fn elliptic_with_equal_axes_is_the_circle() {
    let make = |kind: SourceKind| {
        let mut s = small("glare-flare", 160, 120);
        let src = &mut glare(&mut s).sources[0];
        src.kind = kind;
        src.a = 0.3;
        src.b = 0.3;
        src.halo = true;
        src.flare = false;
        s
    };
    let e = run("elliptic a = b = 0.3", &make(SourceKind::Elliptic));
    let c = run("circle a = 0.3", &make(SourceKind::Circle));
    assert_bounded("elliptic a = b", &e);
    let (Shape2D::Ellipse { a, b, .. }, Shape2D::Circle { r }) =
        (&e.frame.sources[0].shape, &c.frame.sources[0].shape)
    else {
        panic!("shapes");
    };
    assert!((a - r).abs() < 1e-9 && (b - r).abs() < 1e-9, "{a} {b} {r}");
    let d = error_stats(&e.frame.levels(), &c.frame.levels()).unwrap();
    assert!(
        d.max <= 1.0 + 1e-9,
        "ellipse vs circle: max {} levels",
        d.max
    );
    // The references agree to f64 rounding.
    let dr = error_stats(&e.reference, &c.reference).unwrap();
    assert!(dr.max < 1e-6, "references differ by {}", dr.max);
}

// ---------------------------------------------------------------- directivity

/// Directivity perpendicular to the view (D ⟂ eye − P₀, c_D = 0): c_D^e_directivity
/// = 0, so num = 0 and the line intensity 0 — no flare lines, and the noise
/// generator is left out of the elaboration; the bloom is still there but weaker:
/// its factor 0.75 + 0.25·c_D gives exactly ¾ of the facing source's A (point) or B
/// (extended). The elliptic source (its plane faces D) is seen edge-on: a segment
/// of length 2a on screen. Within the general bound.
#[test]
fn directivity_perpendicular() {
    for kind in [SourceKind::Point, SourceKind::Elliptic] {
        let make = |d: Option<[f64; 3]>| {
            let mut s = small("glare-flare", 160, 120);
            let src = &mut glare(&mut s).sources[0];
            src.kind = kind;
            src.directivity = d;
            src.halo = true;
            s
        };
        let tag = format!("{kind:?} with D ⟂ view");
        let side = run(&tag, &make(Some([1.0, 0.0, 0.0])));
        let facing = run(&format!("{kind:?} facing"), &make(Some([0.0, 0.0, 1.0])));
        assert_bounded(&tag, &side);
        assert!(side.frame.sources[0].flare.is_none(), "{tag}");
        assert!(side.frame.lines[0].is_empty());
        assert!(left_out(&side.frame, "gaussian_noise"), "{tag}");
        assert!(facing.frame.sources[0].flare.is_some());
        let ratio = match (side.frame.sources[0].bloom, facing.frame.sources[0].bloom) {
            (Some(Bloom::Point { a: x, .. }), Some(Bloom::Point { a: y, .. })) => x / y,
            (Some(Bloom::Extended { b: x, .. }), Some(Bloom::Extended { b: y, .. })) => x / y,
            other => panic!("{tag}: {other:?}"),
        };
        assert!((ratio - 0.75).abs() < 1e-12, "{tag}: bloom ratio {ratio}");
        let sum = |r: &Run| r.reference.iter().map(|p| p[1]).sum::<f64>();
        assert!(sum(&side) > 0.0 && sum(&side) < sum(&facing), "{tag}");
        if kind == SourceKind::Elliptic {
            let Shape2D::Ellipse { a, b, .. } = side.frame.sources[0].shape else {
                panic!("shape");
            };
            assert!(b.abs() < 1e-9 && a > 1.0, "{tag}: a {a} b {b}");
        }
    }
}

// ---------------------------------------------------------------- the coordinate range

/// A source larger than the coordinate range (a circle of radius 1000 units at 20:
/// 13 500 px on screen, beyond ±8191): its quads are fitted to the range (half-side
/// 8191 − |centre|), the RAM tables computed over the fitted frame; the whole frame
/// lies inside the disc and saturates, exactly as the reference.
#[test]
fn source_larger_than_the_coordinate_range() {
    let mut s = small("glare-flare", 160, 120);
    let src = &mut glare(&mut s).sources[0];
    src.kind = SourceKind::Circle;
    src.a = 1000.0;
    src.halo = true;
    let r = run("circle of 13 500 px", &s);
    let Shape2D::Circle { r: rad } = r.frame.sources[0].shape else {
        panic!()
    };
    assert!(rad > COORD_LIMIT_PX);
    assert_eq!(r.stats.max, 0.0);
    assert!(r.frame.levels().iter().all(|p| p == &[255.0; 3]));
    for p in r.frame.prims.iter().filter(|p| p.kind != "flare") {
        assert_eq!(p.walked, 160 * 120, "{p:?}");
    }
}

/// `fit_area` keeps a quad inside ±COORD_LIMIT_PX (empty when the centre is out of
/// range) and leaves one that fits alone; `line_fits` accepts a line whose
/// rectangle stays a pixel inside the range and rejects one that leaves it.
#[test]
fn quads_fit_the_coordinate_range() {
    let a = |c: [f64; 2], h: f64| AreaPrim {
        center: c,
        half_px: h,
        phi: 0.3,
        d_max_px: 10.0,
    };
    assert_eq!(fit_area(&a([80.0, 60.0], 300.0)).half_px, 300.0);
    assert_eq!(fit_area(&a([8000.0, 60.0], 500.0)).half_px, 191.0);
    assert_eq!(fit_area(&a([60.0, -8100.0], 500.0)).half_px, 91.0);
    assert_eq!(fit_area(&a([9000.0, 0.0], 500.0)).half_px, 0.0);
    assert_eq!(fit_area(&a([1e300, 0.0], 500.0)).half_px, 0.0);
    let fitted = fit_area(&a([8000.0, 60.0], 500.0));
    assert_eq!((fitted.phi, fitted.d_max_px), (0.3, 10.0));
    assert!(line_fits([80.0, 60.0], 0.5, 4000.0, 2000.0));
    assert!(!line_fits([5000.0, 60.0], 0.0, 4000.0, 1.0));
    assert!(line_fits([5000.0, 60.0], std::f64::consts::PI, 4000.0, 1.0));
    assert!(!line_fits([60.0, 8000.0], 0.0, 10.0, 500.0));
    assert!(!line_fits([1e12, 0.0], 0.0, 1.0, 1.0));
}

/// Sources far outside the coordinate range (a fluctuating source whose patches
/// scatter over 10⁶ units: centres ~10⁷ px away) and a source 7000 px above the
/// screen with lines up to 4000 px long: the frame renders (the generator
/// saturates the out-of-range centres, counted; area quads are empty; lines whose
/// rectangle would leave the range are culled, which once made the interpolator's
/// fourth corner overflow), nothing reaches the 96 × 64 screen, and the frame
/// equals the background, as does the reference to within its half-level cut-off.
#[test]
fn sources_beyond_the_coordinate_range() {
    let mut s = small("leaves", 96, 64);
    glare(&mut s).sources[0]
        .fluctuation
        .as_mut()
        .unwrap()
        .spread = 1e6;
    let r = run("patches 10⁷ px away", &s);
    assert_eq!(rgb(&r.frame), r.frame.base);
    assert!(saturations(&r.frame, "polygon_variable_generator") > 0);
    assert!(!r.frame.prims.iter().any(|p| p.kind == "flare"));
    assert!(r.stats.max <= 0.5 + 1e-9, "max {}", r.stats.max);

    let mut s = small("glare-flare", 96, 64);
    let cam = CameraView::new(&s.camera, s.image);
    let f_px = px_per_deg(&cam) * 180.0 / std::f64::consts::PI;
    let g = glare(&mut s);
    // Screen y = 32 − f·Y/20 = −7000.
    g.sources[0].position = [0.0, 7032.0 / f_px * 20.0, -20.0];
    g.model.flare_len_k_deg = 300.0;
    let r = run("lines from 7000 px above", &s);
    let c = r.frame.sources[0].center;
    assert!((c[1] + 7000.0).abs() < 1e-6, "{c:?}");
    let drawn = r.frame.prims.iter().filter(|p| p.kind == "flare").count();
    let n = r.frame.lines[0].len();
    assert!(drawn > 0 && drawn < n, "{drawn} of {n} lines drawn");
    assert_eq!(rgb(&r.frame), r.frame.base);
    assert!(r.stats.max <= 0.5 + 1e-9, "max {}", r.stats.max);
}

// ---------------------------------------------------------------- chaos map

/// The chaos map in a leaves-like scene (96 × 64, 12 patches, 200 frames) with z →
/// 1 (1.0001), z → 2 (1.9999), a → 0 (10⁻⁹) and a → 1 (1 − 10⁻⁶): every frame
/// renders finite within the general bound; each patch's level S_i(t) lies in
/// [0, 1) and is the chaos unit's own state after t steps (so each patch source is
/// the host's `source_glare` at intensity I·S_i; S_i = 0 is the intensity-0 case).
/// With a → 0 the right branch (S − a)/(1 − a) and with a → 1 the left branch
/// S + u·S^z (u = (1 − a)/a^z ≈ 10⁻⁶) are both ≈ the identity, so the patches creep:
/// in u0.32 states, with A = round(a·2³²) (4 LSBs for a = 10⁻⁹), a step of a state
/// above A (a → 0) moves it down by at most A + 1 LSBs, and a step of a state at or
/// below A (a → 1) moves it up by at least 1 LSB (the MinStep escape: never stuck)
/// and at most u·2³² + 2 ≈ 4297 LSBs — over 200 frames ≤ 2.3·10⁻⁷ and ≤ 2·10⁻⁴ of
/// full scale, unless the state crosses A and is reinjected.
#[test]
fn chaos_map_extremes_render() {
    for (a, z) in [(0.8, 1.0001), (0.8, 1.9999), (1e-9, 1.5), (1.0 - 1e-6, 1.5)] {
        let mut s = small("leaves", 96, 64);
        let g = glare(&mut s);
        g.model.chaos_a = a;
        g.model.chaos_z = z;
        g.frame = 200;
        let tag = format!("chaos a = {a}, z = {z}");
        let r = run(&tag, &s);
        assert_bounded(&tag, &r);
        let (u, mut st) = chaos_unit(&s, 0, 12).unwrap();
        let mut walk = st.clone();
        let mut ctr = Default::default();
        u.run_trace(&mut st, 200, &mut ctr);
        let scale = (u.state_max() + 1) as f64;
        let screens = screen_sources(&s).unwrap();
        let g = s.glare.as_ref().unwrap();
        assert_eq!(r.frame.patch_levels.len(), 12);
        for (k, lvl) in r.frame.patch_levels.iter().enumerate() {
            assert!((0.0..1.0).contains(lvl), "{tag}: patch {k} level {lvl}");
            assert_eq!(*lvl, st.s[k] as f64 / scale, "{tag}: patch {k}");
            let want = source_glare(
                &screens[k],
                screens[k].intensity * lvl,
                &g.determinants,
                &g.model,
            );
            assert_eq!(r.frame.sources[k], want, "{tag}: patch {k}");
        }
        // Step by step, the creeping bounds of the near-identity branches.
        let big_a = u.a_code();
        let u_lsb = (1.0 - a) / a.powf(z) * scale;
        for _ in 0..200 {
            for k in 0..12 {
                let s0 = walk.s[k];
                let s1 = u.step(s0, &mut ctr);
                if a < 1e-3 && s0 > big_a && s1 <= s0 {
                    assert!(s0 - s1 <= big_a + 1, "{tag}: {s0} → {s1}");
                }
                if a > 1.0 - 1e-3 && s0 <= big_a {
                    assert!(s1 > s0, "{tag}: {s0} stuck");
                    assert!((s1 - s0) as f64 <= u_lsb + 2.0, "{tag}: {s0} → {s1}");
                }
                walk.s[k] = s1;
            }
        }
        assert_eq!(
            walk.s, st.s,
            "{tag}: step-by-step and the unit's trace differ"
        );
    }
}

// ---------------------------------------------------------------- f64 reference

/// The f64 formulas at extreme arguments. Decided behaviour: `bloom_point` at θ = 0
/// with θ₀ → 0 is A/θ₀^m while θ₀^m is a normal f64 (≥ 2.2·10⁻³⁰⁸), then
/// A/2.2·10⁻³⁰⁸ = 4.5·10³⁰⁷·A (e.g. θ₀ = 10⁻³⁰⁰, m = 8, where θ₀^m underflows to 0),
/// never above f64::MAX (not +∞); with A = 0 it is 0 (not 0/0 = NaN); the same holds
/// for the B/(θ + θ₁)^m term of `bloom_extended`. `halo` with α → 0 is
/// 0 off the ring and C on it. Distances to degenerate outlines are the distances to
/// the point or segment they collapse to.
#[test]
fn reference_functions_at_extremes() {
    for t0 in [1e-9, 1e-50, 1e-300, 5e-324] {
        for m in [0.5, 1.5, 2.8, 8.0] {
            for a in [0.0, 1e-300, 1.0, 1e9, 1e46] {
                for theta in [0.0, 1e-300, 1e-9, 1.0, 180.0, 1e9] {
                    let v = bloom_point(theta, a, t0, m);
                    assert!(
                        v.is_finite() && v >= 0.0,
                        "θ {theta} A {a} θ₀ {t0} m {m}: {v}"
                    );
                    if a == 0.0 {
                        assert_eq!(v, 0.0);
                    }
                }
            }
        }
    }
    assert_eq!(bloom_point(0.0, 1.0, 1e-300, 8.0), 1.0 / f64::MIN_POSITIVE);
    assert_eq!(bloom_point(0.0, 1e300, 1e-300, 8.0), f64::MAX);
    assert_eq!(bloom_point(0.0, 0.0, 1e-300, 8.0), 0.0);
    let v = bloom_point(0.0, 1.0, 1e-9, 8.0);
    assert!((v / 1e72 - 1.0).abs() < 1e-12, "{v}");
    // Non-increasing in θ even across the cap.
    let mut prev = f64::INFINITY;
    for k in 0..200 {
        let theta = 1e-300 * 10f64.powf(k as f64 * 1.5);
        let v = bloom_point(theta, 29.0, 1e-300, 8.0);
        assert!(v <= prev, "θ {theta}: {v} > {prev}");
        prev = v;
    }
    let mut p = GlareModel {
        bloom_theta1_deg: 5e-324,
        bloom_m: 8.0,
        bloom_w_deg: 5e-324,
        ..GlareModel::default()
    };
    for (a, b) in [(0.0, 0.0), (1.0, 1.0), (1e9, 1e9)] {
        for t in [0.0, 1e-300, 1.0, 1e9] {
            let v = bloom_extended(t, a, b, &p);
            assert!(v.is_finite() && v >= 0.0, "extended θ {t} A {a} B {b}: {v}");
        }
    }
    assert_eq!(bloom_extended(0.0, 0.0, 0.0, &p), 0.0);
    p.halo_alpha_deg = 5e-324;
    assert_eq!(halo(3.0, 100.0, 568.0, &p), 0.0);
    let on_ring = p.halo_radius_deg;
    assert_eq!(halo(on_ring, 100.0, 568.0, &p), 100.0);
    assert!(halo(1e300, 1e9, 900.0, &GlareModel::default()).is_finite());
    // Flare profile and a line of zero length or width.
    assert_eq!(flare_profile(0.0, 0.0), 1.0);
    assert_eq!(flare_profile(f64::MAX, 0.0), 0.0);
    let line = FlareLine {
        angle: 0.0,
        length_px: 0.0,
        width_px: 1.0,
        intensity: 1e9,
    };
    assert_eq!(flare_line_at(&line, 0.0, 0.0), 0.0);
    // Degenerate outlines.
    assert_eq!(ellipse_distance(3.0, 4.0, 0.0, 0.0), 5.0);
    assert_eq!(ellipse_distance(3.0, 4.0, 2.0, 0.0), f64::hypot(1.0, 4.0));
    assert!((ellipse_distance(3.0, 0.0, 1.0, 1e-300) - 2.0).abs() < 1e-12);
    assert_eq!(ellipse_distance(0.5, 0.0, 1.0, 1e-300), 0.0);
    let pt = [[1.0, 1.0]; 4];
    assert_eq!(polygon_distance(&pt, 4.0, 5.0), 5.0);
    assert_eq!(polygon_distance(&pt, 1.0, 1.0), 0.0);
    // Collinear: the segment from (0,0) to (2,0).
    let seg = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    assert_eq!(polygon_distance(&seg, 5.0, 0.0), 3.0);
    assert_eq!(polygon_distance(&seg, 1.0, 2.0), 2.0);
    assert_eq!(polygon_distance(&seg, 1.5, 0.0), 0.0);
    // A proper triangle is still solid.
    let tri = [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]];
    assert_eq!(polygon_distance(&tri, 1.0, 1.0), 0.0);
    assert_eq!(polygon_distance(&tri, -3.0, 0.0), 3.0);
}

/// The reference image of sources whose profiles are at the extremes (a spike
/// point bloom with θ₀ = 10⁻³⁰⁰ centred exactly on a pixel centre, so θ = 0 there,
/// with a colour channel of 0; a huge halo; a line of enormous length and width)
/// stays finite and in [0, max].
#[test]
fn reference_image_at_extremes() {
    use glare_pipeline::reference::glare_model::{FlareParams, SourceGlare};
    let det = Determinants::default();
    let p = GlareModel::default();
    let src = |bloom, halo, flare| SourceGlare {
        center: [4.5, 3.5],
        shape: Shape2D::Point,
        px_per_deg: 4.7,
        color: [1.0, 0.0, 0.5],
        bloom,
        halo,
        flare,
    };
    let sources = vec![
        src(
            Some(Bloom::Point {
                a: 1e46,
                theta0: 1e-300,
                m: 8.0,
            }),
            Some(1e300),
            None,
        ),
        src(
            Some(Bloom::Extended { a: 1e300, b: 1e300 }),
            None,
            Some(FlareParams {
                num: 2,
                len_deg: 1e300,
                width_deg: 1e300,
                intensity: 1e300,
                spread_rad: 1.0,
                base_rad: 0.0,
            }),
        ),
    ];
    let lines = vec![
        vec![],
        vec![FlareLine {
            angle: 0.3,
            length_px: 1e300,
            width_px: 1e300,
            intensity: 1e300,
        }],
    ];
    let base = vec![[3.0; 3]; 9 * 7];
    let img = reference_image(9, 7, &base, &sources, &lines, &det, &p, 255.0);
    for px in &img {
        for v in px {
            assert!(v.is_finite() && (0.0..=255.0).contains(v), "{v}");
        }
    }
    // Green is 0 in the colour: only the background's 3 remains there.
    assert_eq!(img[3 * 9 + 4][1], 3.0);
    assert_eq!(img[3 * 9 + 4][0], 255.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The f64 formulas never give NaN over their valid argument ranges, extremes
    /// included (θ₀, θ₁, w, α down to the smallest subnormal; m up to 8).
    #[test]
    fn reference_formulas_never_nan(
        theta in prop_oneof![Just(0.0), 0.0..1e-300f64, 0.0..180.0f64, 0.0..1e12f64],
        a in prop_oneof![Just(0.0), 0.0..1e50f64],
        t0_exp in -323.0..2.0f64,
        m in 0.5..8.0f64,
        n in 0.5..10.0f64,
        lambda in 300.0..900.0f64,
    ) {
        let t0 = 10f64.powf(t0_exp).max(5e-324);
        let v = bloom_point(theta, a, t0, m);
        prop_assert!(v.is_finite() && v >= 0.0, "bloom_point {v}");
        let p = GlareModel {
            bloom_theta1_deg: t0,
            bloom_w_deg: t0,
            bloom_m: m,
            bloom_n: n,
            halo_alpha_deg: t0,
            ..GlareModel::default()
        };
        let v = bloom_extended(theta, a, a, &p);
        prop_assert!(v.is_finite() && v >= 0.0, "bloom_extended {v}");
        let v = halo(theta, a, lambda, &p);
        prop_assert!(v.is_finite() && v >= 0.0, "halo {v}");
    }
}

// ---------------------------------------------------------------- random combinations

/// A value in [lo, hi]: an end, uniform, or log-uniform (so tiny values are drawn).
fn pick(rng: &mut rand_chacha::ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    use rand::Rng;
    match rng.random_range(0..4) {
        0 => lo,
        1 => hi,
        2 => lo + (hi - lo) * rng.random::<f64>(),
        _ => {
            let l = lo.max(1e-300).ln();
            (l + (hi.ln() - l) * rng.random::<f64>()).exp()
        }
    }
}

/// 300 scenes (48 × 32, seeded) with many extremes at once: every source kind, any
/// intensity in [0, 10⁹], sizes up to 10³ units, random directivity, positions from
/// 10⁻⁶ to 10⁶ units deep, every model constant and exponent across its valid
/// range (θ₀, θ₁, w, α down to 10⁻³⁰⁰; m to 8), random hardware widths, ambient to
/// 10⁶. Behaviour: valid scenes never panic; they render with every level and
/// every reference value finite in [0, 255], or fail with an error naming a
/// `glare.` field (in practice an extended source whose outline reaches behind the
/// eye's plane: `glare.sources[0].a`).
#[test]
fn random_extreme_combinations() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
    let names = ["glare-point", "glare-elliptic", "glare-flare", "leaves"];
    let kinds = [
        SourceKind::Point,
        SourceKind::Circle,
        SourceKind::Elliptic,
        SourceKind::Cylindrical,
        SourceKind::Polygon,
    ];
    let (mut rendered, mut errors) = (0, 0);
    for case in 0..300 {
        let mut s = small(names[case % 4], 48, 32);
        s.seed = rng.random();
        let g = glare(&mut s);
        let src = &mut g.sources[0];
        src.kind = kinds[rng.random_range(0..5)];
        src.intensity = pick(&mut rng, 0.0, 1e9);
        src.a = pick(&mut rng, 0.0, 1e3);
        src.b = pick(&mut rng, 0.0, src.a);
        src.bloom = rng.random();
        src.halo = rng.random();
        src.flare = rng.random();
        if src.kind == SourceKind::Polygon {
            let p = src.position;
            let n = rng.random_range(2..6);
            src.vertices = (0..n)
                .map(|_| {
                    let mut q = p;
                    for c in &mut q[..2] {
                        *c += pick(&mut rng, 0.0, 5.0) * (rng.random::<f64>() - 0.5);
                    }
                    q[2] += rng.random::<f64>() - 0.5;
                    q
                })
                .collect();
        }
        if rng.random_bool(0.3) {
            src.directivity = Some([
                rng.random::<f64>() - 0.5,
                rng.random::<f64>() - 0.5,
                rng.random::<f64>() - 0.5 + 1e-3,
            ]);
        }
        if rng.random_bool(0.2) {
            src.position = [
                pick(&mut rng, -1e3, 1e3),
                pick(&mut rng, -1e3, 1e3),
                -pick(&mut rng, 1e-6, 1e6),
            ];
        }
        let m = &mut g.model;
        m.point_theta0_deg = pick(&mut rng, 1e-300, 90.0);
        m.point_m = pick(&mut rng, 0.5, 8.0);
        m.bloom_m = pick(&mut rng, 0.5, 8.0);
        m.bloom_n = pick(&mut rng, 0.5, 10.0);
        m.bloom_w_deg = pick(&mut rng, 1e-300, 90.0);
        m.bloom_theta1_deg = pick(&mut rng, 1e-300, 90.0);
        m.halo_alpha_deg = pick(&mut rng, 1e-300, 90.0);
        m.halo_radius_deg = pick(&mut rng, 0.0, 90.0);
        m.halo_k = pick(&mut rng, 0.0, 1e6);
        m.bloom_k = pick(&mut rng, 0.0, 1e6);
        m.point_k = pick(&mut rng, 0.0, 1e6);
        m.flare_num_k = pick(&mut rng, 0.0, 1e6);
        m.flare_len_k_deg = pick(&mut rng, 0.0, 1e3);
        m.flare_width_k_deg = pick(&mut rng, 0.0, 1e3);
        m.flare_intensity_k = pick(&mut rng, 0.0, 1e6);
        m.flare_spread_rad = pick(&mut rng, 0.0, 10.0);
        m.flare_max_lines = rng.random_range(0..100);
        m.e_intensity = pick(&mut rng, 0.0, 8.0);
        m.e_size = pick(&mut rng, 0.0, 8.0);
        m.e_ambient = pick(&mut rng, 0.0, 8.0);
        m.e_mist = pick(&mut rng, 0.0, 8.0);
        m.size_ref_deg = pick(&mut rng, 1e-300, 90.0);
        m.chaos_a = pick(&mut rng, 1e-300, 0.999_999);
        m.chaos_z = 1.0 + pick(&mut rng, 1e-6, 0.999_999);
        g.determinants.ambient = pick(&mut rng, 0.0, 1e6);
        g.determinants.mist = pick(&mut rng, 0.0, 1e3);
        g.determinants.age = pick(&mut rng, 0.0, 120.0);
        g.hw.shape_log2 = rng.random_range(1..=8);
        g.hw.falloff_log2 = rng.random_range(1..=12);
        g.hw.shape_bits = rng.random_range(1..=16);
        g.hw.falloff_bits = rng.random_range(1..=20);
        g.hw.weight_bits = rng.random_range(1..=12);
        g.hw.coord_frac_bits = rng.random_range(2..=16);
        g.hw.fb_bits = rng.random_range(1..=16);
        g.frame = rng.random_range(0..50);
        if s.validate().is_err() {
            continue;
        }
        match std::panic::catch_unwind(|| render_and_predict(&s)) {
            Err(_) => panic!("case {case} panicked: {:?}", s.glare),
            Ok(Err(e)) => {
                assert!(e.field().starts_with("glare."), "case {case}: {e}");
                errors += 1;
            }
            Ok(Ok((f, _, _))) => {
                rendered += 1;
                let lv = reference_levels(&s, &f).unwrap();
                for v in lv.iter().chain(f.levels().iter()).flatten() {
                    assert!(
                        v.is_finite() && (0.0..=255.0).contains(v),
                        "case {case}: {v} in {:?}",
                        s.glare
                    );
                }
            }
        }
    }
    println!("{rendered} rendered, {errors} errors naming a glare field");
    assert!(rendered > 250, "{rendered}");
}
