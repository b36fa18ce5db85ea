//! clipper against its f64 twin, its drivers against each other, and a scene whose
//! objects cross the near plane rendered through it.
//!
//! Bound (one cut, docs/units.md#clipper). The inputs are raw words, so the unit and
//! the twin see the same vertices and the same plane distances (exact integers in the
//! unit, exact in f64 for these widths): both classify the input alike. A cut vertex
//! is I + t·(O − I) with t rounded to `t_frac_bits` (|δt| ≤ ½·2⁻ᵀ) and each clip word
//! rounded to the clip LSB, so each of x, y, z, w is within
//! e = ½·LSB_clip + ½·2⁻ᵀ·|O − I| of the exact cut. The screen position X/2w with
//! X = (x + w)·W moves by at most (W·(e + e) + 2·|x_s|·e)/(2·w) for w ≥ the smallest w
//! (first order; the test takes the cut's w minus e), plus ½ LSB of the screen format
//! for the output division; depth (z + w)/2w by (2e + 2·depth·e)/(2w) + ½ LSB_attr.
//! The attribute parameter s = t·w_O/w_new is off by at most
//! ½·2⁻ᵀ·(1 + w_O/w_new) + s·e/w_new + ½·2⁻ᵀ (its own rounding), so an attribute by
//! |A_O − A_I|·δs + ½ LSB_attr. A vertex the clipper did not make (an input vertex)
//! is only divided: ½ LSB.
//!
//! Cases where a later plane meets a cut vertex within the bound of its distance
//! would classify differently under any rounding; they are skipped and counted, and
//! the test asserts they are rare.

mod common;

use glare_pipeline::frame::chip::elaborate;
use glare_pipeline::frame::reproduce::frame_error;
use glare_pipeline::frame::run::render;
use glare_pipeline::reference::clipper::{ClipSetup, ClipVertexF};
use glare_pipeline::scene::builtin::{builtin, BUILTIN_NAMES};
use glare_pipeline::scene::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use glare_pipeline::scene::builtin_glare::GLARE_BUILTIN_NAMES;
use glare_pipeline::scene::builtin_showcase::SHOWCASE_NAMES;
use glare_pipeline::scene::clip::clip_needed;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rtl_model::driver::{run_batch, run_span, run_tick};
use rtl_model::units::clipper::{
    AttrLerp, ClipIn, ClipStats, ClipVertex, Clipper, ClipperConfig, NearFar,
};
use rtl_model::{Counters, Unit};

/// The configs the bound is checked at: the default, and a narrow one (12.8 clip
/// words, 10-bit t, 2 sub-pixel bits, 8.8 attributes, a small guard band, near only,
/// attributes at t).
fn configs() -> Vec<ClipperConfig> {
    vec![
        ClipperConfig::default(),
        ClipperConfig {
            attrs: 3,
            clip_int_bits: 12,
            clip_frac_bits: 8,
            attr_int_bits: 8,
            attr_frac_bits: 8,
            t_frac_bits: 10,
            screen_int_bits: 11,
            subpixel_bits: 2,
            viewport_width: 300,
            viewport_height: 200,
            guard_min: -600,
            guard_max: 900,
            near_far: NearFar::Near,
            attr_lerp: AttrLerp::Homogeneous,
        },
    ]
}

fn setup(c: &ClipperConfig) -> ClipSetup {
    ClipSetup {
        width: c.viewport_width as f64,
        height: c.viewport_height as f64,
        guard_min: c.guard_min as f64,
        guard_max: c.guard_max as f64,
        far: c.near_far == NearFar::Both,
        screen_attrs: c.attr_lerp == AttrLerp::Screen,
    }
}

/// Near and far of the random triangles' perspective projection.
const NEAR: f64 = 0.5;
const FAR: f64 = 3.5;

/// A random triangle in clip space as a GL perspective projection makes it (near 0.5,
/// far 3.5): view depth −z_e = w in [−1, 4] (some behind the eye, some beyond the far
/// plane), z = A·z_e + B, x/w and y/w spread wide enough to cross the guard band;
/// attributes in [−2, 2].
fn random_tri(u: &Clipper, rng: &mut ChaCha8Rng) -> ClipIn {
    let mut ctr = Counters::default();
    let spread = 2.0 * u.config().guard_max as f64 / u.config().viewport_width as f64;
    let (a, b) = (
        -(FAR + NEAR) / (FAR - NEAR),
        -2.0 * FAR * NEAR / (FAR - NEAR),
    );
    let mut tri = ClipIn::default();
    for (k, v) in tri.v.iter_mut().enumerate() {
        let w: f64 = rng.random_range(-1.0..4.0);
        let ww = w.abs().max(0.25);
        let c = [
            rng.random_range(-2.0 * spread..2.0 * spread) * ww,
            rng.random_range(-2.0 * spread..2.0 * spread) * ww,
            a * -w + b,
            w,
        ];
        let attrs: Vec<f64> = (0..u.attrs())
            .map(|_| rng.random_range(-2.0..2.0))
            .collect();
        *v = u.vertex_from_f64(k, c, &attrs, &mut ctr).unwrap();
    }
    tri
}

fn to_f64(u: &Clipper, v: &ClipVertex) -> ClipVertexF {
    let l = u.clip_lsb();
    ClipVertexF {
        c: [v.x, v.y, v.z, v.w].map(|r| r as f64 * l),
        attrs: v.attrs[..u.attrs() as usize]
            .iter()
            .map(|&r| r as f64 * u.attr_lsb())
            .collect(),
    }
}

/// Which planes the twin cuts on this triangle (bit p), and whether some distance a
/// later plane takes of a cut vertex lies within `margin` of 0.
fn twin_cuts(s: &ClipSetup, tri: &[ClipVertexF; 3], margin: [f64; 2]) -> (u32, bool) {
    if s.culled(tri) {
        return (0, false);
    }
    let mut poly: Vec<ClipVertexF> = tri.to_vec();
    let mut cuts = 0;
    let mut close = false;
    for p in 0..6 {
        if p == 1 && !s.far {
            continue;
        }
        let d: Vec<f64> = poly.iter().map(|v| s.distances(&v.c)[p]).collect();
        let m = if p < 2 { margin[0] } else { margin[1] };
        if cuts != 0 && d.iter().any(|x| x.abs() < m) {
            close = true;
        }
        if d.iter().any(|&x| x < 0.0) {
            cuts |= 1 << p;
            // Clip by this plane alone (the twin's own stage).
            poly = s.clip_stage(&poly, p);
            if poly.is_empty() {
                break;
            }
        }
    }
    (cuts, close)
}

/// Largest |O − I| over the clip words of the triangle's edges.
fn max_delta(tri: &[ClipVertexF; 3]) -> f64 {
    let mut m: f64 = 0.0;
    for a in 0..3 {
        let b = (a + 1) % 3;
        for k in 0..4 {
            m = m.max((tri[a].c[k] - tri[b].c[k]).abs());
        }
    }
    m
}

#[test]
fn one_cut_or_none_is_within_the_bound_of_the_twin() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xc11f);
    for cfg in configs() {
        let u = cfg.build().unwrap();
        let s = setup(&cfg);
        let (mut checked, mut skipped, mut cut_checked, mut culled) = (0, 0, 0, 0);
        let tf = (-(cfg.t_frac_bits as f64)).exp2();
        for _ in 0..20_000 {
            let tri = random_tri(&u, &mut rng);
            let tf64: [ClipVertexF; 3] = std::array::from_fn(|k| to_f64(&u, &tri.v[k]));
            let e = 0.5 * u.clip_lsb() + 0.5 * tf * max_delta(&tf64);
            // A distance within its error of 0: 2e for near and far, (W + 2g)·(2e) for
            // the guard band's edges.
            let dmargin = [
                2.0 * e,
                2.0 * e
                    * (cfg.viewport_width.max(cfg.viewport_height) as f64
                        + 2.0 * cfg.guard_max.max(-cfg.guard_min) as f64),
            ];
            let (cuts, close) = twin_cuts(&s, &tf64, dmargin);
            if cuts.count_ones() > 1 {
                continue;
            }
            if close {
                skipped += 1;
                continue;
            }
            let mut st = ClipStats::default();
            let mut ctr = Counters::default();
            let (out, _) = u.clip(&tri, &mut st, &mut ctr);
            let want = s.clip(&tf64);
            assert_eq!(out.n as usize, want.len(), "vertex count: {tri:?}");
            if want.is_empty() {
                culled += 1;
                continue;
            }
            checked += 1;
            cut_checked += u32::from(cuts != 0);
            assert_eq!(out.clipped, cuts != 0);
            let sl = u.screen_lsb();
            let al = u.attr_lsb();
            let want_poly = s.clip_polygon(&tf64);
            for (k, (got, tw)) in out.vertices().iter().zip(&want).enumerate() {
                let cv = &want_poly[k];
                // An input vertex is only divided.
                let made = !tf64.iter().any(|v| v.c == cv.c);
                let ec = if made { e } else { 0.0 };
                let w = cv.c[3] - ec;
                assert!(w > 0.0);
                let bx = (cfg.viewport_width as f64 * 2.0 * ec + 2.0 * tw.x.abs() * ec) / (2.0 * w)
                    + 0.5 * sl
                    + 1e-9;
                let by = (cfg.viewport_height as f64 * 2.0 * ec + 2.0 * tw.y.abs() * ec)
                    / (2.0 * w)
                    + 0.5 * sl
                    + 1e-9;
                let bd = (2.0 * ec + 2.0 * tw.depth.abs() * ec) / (2.0 * w) + 0.5 * al + 1e-9;
                let gx = got.x as f64 * sl;
                let gy = got.y as f64 * sl;
                assert!(
                    (gx - tw.x).abs() <= bx,
                    "x {gx} vs {} (bound {bx}) {tri:?}",
                    tw.x
                );
                assert!((gy - tw.y).abs() <= by, "y {gy} vs {} (bound {by})", tw.y);
                // Depth: the twin's may lie outside the attribute range only if the
                // unit saturated (counted).
                let gd = got.depth as f64 * al;
                assert!(
                    (gd - tw.depth).abs() <= bd || ctr.saturations > 0,
                    "depth {gd} vs {} (bound {bd})",
                    tw.depth
                );
                // Attributes: δs (or δt) times the largest attribute step.
                let amax = (0..u.attrs() as usize)
                    .map(|j| {
                        (0..3)
                            .map(|a| (tf64[a].attrs[j] - tf64[(a + 1) % 3].attrs[j]).abs())
                            .fold(0.0, f64::max)
                    })
                    .fold(0.0, f64::max);
                // δs ≤ ½·2⁻ᵀ·w_O/w_new + s·e/w_new + ½·2⁻ᵀ, w_O ≤ the largest |w|.
                let wmax = tf64.iter().map(|v| v.c[3].abs()).fold(0.0, f64::max);
                let ds = if made {
                    0.5 * tf * (1.0 + wmax / w) + ec / w
                } else {
                    0.0
                };
                for (j, (&ga, &ta)) in got.attrs.iter().zip(&tw.attrs).enumerate() {
                    let ba = amax * ds + 0.5 * al + 1e-9;
                    let g = ga as f64 * al;
                    assert!((g - ta).abs() <= ba, "attr {j}: {g} vs {ta} (bound {ba})");
                }
                // Every vertex handed on is inside the screen format.
                let lim = (1i64 << (cfg.screen_int_bits - 1)) << cfg.subpixel_bits;
                assert!(got.x >= -lim && got.x < lim && got.y >= -lim && got.y < lim);
            }
        }
        assert!(checked > 1000, "{checked} checked");
        assert!(cut_checked > 500, "{cut_checked} cut cases checked");
        assert!(culled > 100, "{culled} culled");
        // Rare: under 1 in 10 (none at the default widths, 8 % at the narrow ones).
        assert!(skipped * 10 < checked, "{skipped} skipped of {checked}");
        eprintln!("{checked} checked ({cut_checked} cut), {culled} culled, {skipped} skipped");
    }
}

#[test]
fn every_polygon_handed_on_fits_the_interpolator_and_counts_add_up() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for cfg in configs() {
        let u = cfg.build().unwrap();
        let s = setup(&cfg);
        let mut st = ClipStats::default();
        let mut ctr = Counters::default();
        let mut out_n = 0;
        let mut count_diff = 0;
        let mut worst: f64 = 0.0;
        let n = 20_000;
        for _ in 0..n {
            let tri = random_tri(&u, &mut rng);
            let (out, _) = u.clip(&tri, &mut st, &mut ctr);
            let sl = u.screen_lsb();
            for v in out.vertices() {
                let (x, y) = (v.x as f64 * sl, v.y as f64 * sl);
                // How far past the guard band the cut's rounding put it.
                let past = [cfg.guard_min as f64 - x, x - cfg.guard_max as f64]
                    .into_iter()
                    .chain([cfg.guard_min as f64 - y, y - cfg.guard_max as f64])
                    .fold(0.0, f64::max);
                worst = worst.max(past);
            }
            out_n += u64::from(out.n > 0);
            let tf64: [ClipVertexF; 3] = std::array::from_fn(|k| to_f64(&u, &tri.v[k]));
            let drawn = !s.clip(&tf64).is_empty();
            count_diff += u32::from((out.n > 0) != drawn);
        }
        assert_eq!(st.polygons_in, n);
        assert_eq!(st.polygons_out, out_n);
        assert_eq!(st.polygons_in, st.polygons_out + st.polygons_culled);
        assert!(st.polygons_clipped > 0 && st.vertices_generated >= st.polygons_clipped);
        assert_eq!(ctr.overflows, 0);
        // Nothing handed on left the screen format.
        assert_eq!(ctr.saturations, 0);
        eprintln!("guard band overshoot at most {worst} px");
        if cfg == ClipperConfig::default() {
            // The shafts pipeline's guard band keeps 1 − 2⁻ˢ px to the format's edge.
            assert!(
                worst < 1.0 - u.screen_lsb(),
                "{worst} px past the guard band"
            );
        }
        // Drawn or culled as the twin decides, but for triangles rounding tips over.
        assert!(count_diff * 200 < n as u32, "{count_diff} disagree");
    }
}

#[test]
fn drivers_agree_and_count_the_cut_clocks() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for cfg in configs() {
        let u = cfg.build().unwrap();
        let inputs: Vec<ClipIn> = (0..300).map(|_| random_tri(&u, &mut rng)).collect();
        let mut s_span = ClipStats::default();
        let mut c_span = Counters::default();
        let out_span = run_span(&u, &mut s_span, &inputs, &mut c_span);
        common::assert_batch_agrees(
            &u,
            &ClipStats::default(),
            &inputs,
            &out_span,
            &s_span,
            &c_span,
        );
        let mut s_tick = ClipStats::default();
        let mut c_tick = Counters::default();
        let out_tick = run_tick::<_, Vec<u8>>(&u, &mut s_tick, &inputs, &mut c_tick, None).unwrap();
        assert_eq!(out_tick, out_span);
        assert_eq!(s_tick, s_span);
        assert_eq!(c_tick, c_span);
        // Cycles: the stream at II = 3 plus the clocks clipped triangles held it.
        let mut extra = 0;
        let mut st = ClipStats::default();
        for i in &inputs {
            extra += u.clip(i, &mut st, &mut Counters::default()).1;
        }
        assert!(extra > 0);
        let t = u.timing();
        assert_eq!(c_span.cycles, t.span_cycles(inputs.len() as u64) + extra);
        assert_eq!(c_span.stalls, t.span_stalls(inputs.len() as u64) + extra);
        // A stream no plane cuts: the common check, cycles exactly the timing's.
        let inside: Vec<ClipIn> = inputs
            .iter()
            .filter(|i| {
                !u.clip(i, &mut ClipStats::default(), &mut Counters::default())
                    .0
                    .clipped
            })
            .cloned()
            .collect();
        common::assert_drivers_agree(&u, ClipStats::default(), &inside);
        let _ = run_batch(
            &u,
            &mut ClipStats::default(),
            &inside,
            5,
            &mut Counters::default(),
        );
    }
}

#[test]
fn bad_configs_name_their_field() {
    let bad = |f: fn(&mut ClipperConfig), field: &str| {
        let mut c = ClipperConfig::default();
        f(&mut c);
        let e = c.build().unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    };
    bad(|c| c.guard_max = 5000, "clipper.guard_max");
    bad(|c| c.guard_min = -5000, "clipper.guard_min");
    bad(|c| c.viewport_width = 4096, "clipper.viewport_width");
    bad(|c| c.t_frac_bits = 2, "clipper.t_frac_bits");
    bad(|c| c.attrs = 17, "clipper.attrs");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(common::cases()))]

    /// A triangle inside every plane passes untouched: its screen position is the
    /// divide rounded, within ½ LSB of the twin, its attributes the input words.
    #[test]
    fn inside_passes_untouched(xs in prop::array::uniform3(-0.9f64..0.9),
                               ys in prop::array::uniform3(-0.9f64..0.9),
                               ws in prop::array::uniform3(0.5f64..30.0)) {
        let u = Clipper::geforce();
        let mut ctr = Counters::default();
        let mut tri = ClipIn::default();
        for k in 0..3 {
            let a: Vec<f64> = (0..u.attrs()).map(|j| j as f64 * 0.1 + xs[k]).collect();
            tri.v[k] = u.vertex_from_f64(k, [xs[k] * ws[k], ys[k] * ws[k], 0.0, ws[k]], &a, &mut ctr).unwrap();
        }
        let (out, extra) = u.clip(&tri, &mut ClipStats::default(), &mut ctr);
        prop_assert_eq!(extra, 0);
        prop_assert!(!out.clipped);
        let s = setup(u.config());
        let tf: [ClipVertexF; 3] = std::array::from_fn(|k| to_f64(&u, &tri.v[k]));
        let want = s.clip(&tf);
        prop_assert_eq!(out.n as usize, want.len());
        for (k, (g, t)) in out.vertices().iter().zip(&want).enumerate() {
            prop_assert!((g.x as f64 * u.screen_lsb() - t.x).abs() <= 0.5 * u.screen_lsb() + 1e-9);
            prop_assert!((g.y as f64 * u.screen_lsb() - t.y).abs() <= 0.5 * u.screen_lsb() + 1e-9);
            prop_assert_eq!(&g.attrs[..], &tri.v[k].attrs[..]);
        }
    }
}

/// fig6 with the camera 0.1 above the floor, moved in over it (eye at z = 6, the floor
/// reaching z = 10 behind it), looking level with a wide field of view and the near
/// plane at 0.05: the floor runs behind the eye and, at grazing depths, sideways far
/// beyond the guard band, so the clipper is elaborated even at 180 × 120 and cuts
/// triangles. The near plane lies nearer than any floor the view sees (the floor's
/// first visible row is at depth 0.1/tan 35° = 0.14), so near clipping leaves no hole
/// the ray march would fill.
fn fig6_grazing() -> glare_pipeline::scene::format::Scene {
    let mut s = builtin("fig6").unwrap();
    s.image.width = 180;
    s.image.height = 120;
    s.camera.eye = [0.0, 0.1, 6.0];
    s.camera.look_at = [0.0, 0.1, 0.0];
    s.camera.near = 0.05;
    s.camera.fovy_deg = 70.0;
    s.shafts.planes = 12;
    s.shafts.subplanes = 2;
    s
}

#[test]
fn built_ins_at_their_size_leave_the_clipper_out() {
    let names = BUILTIN_NAMES
        .iter()
        .chain(GLARE_BUILTIN_NAMES)
        .chain(SHOWCASE_NAMES)
        .chain(ENVIRONMENT_BUILTIN_NAMES);
    for name in names {
        let s = builtin(name).unwrap();
        let chip = elaborate(&s);
        let c = chip.units.iter().find(|u| u.instance == "clipper").unwrap();
        assert!(!c.present && c.left_out.is_some(), "{name}");
    }
}

#[test]
fn a_camera_over_the_floor_renders_through_the_clipper_near_the_reference() {
    let s = fig6_grazing();
    assert!(clip_needed(&s).is_some());
    let chip = elaborate(&s);
    let c = chip.units.iter().find(|u| u.instance == "clipper").unwrap();
    assert!(c.present && c.gates_nand2 > 0.0);
    let f = render(&s).unwrap();
    let sh = f.shafts.as_ref().unwrap();
    let st = sh.clip_stats.unwrap();
    assert!(st.polygons_clipped > 0, "{st:?}");
    assert!(st.polygons_culled > 0, "{st:?}");
    assert_eq!(st.polygons_in, st.polygons_out + st.polygons_culled);
    let ctr = &sh.counters["clipper"];
    assert_eq!(ctr.overflows, 0);
    let e = frame_error(&s, &f, None).unwrap();
    // fig6 at its own 720 × 480 size renders at a mean |Δ| of 1.32 and an RMS of 7.5
    // levels against the ray march (docs/units.md#clipper); the clipped floor stays at
    // that level.
    assert!(e.total.mean_abs < 2.0, "{:?}", e.total);
    assert!(e.total.rms < 10.0, "{:?}", e.total);
}
