//! Stiff and extreme cases of the light-shafts pipeline (issue 3, DESIGN §4): the light
//! inside the medium (s → 0), ρκ ∈ {0, 10⁻⁶, 10, 1000}, n = 1 and n = 5000, the light
//! behind the camera, intensity 0 and 10⁶, degenerate spot cones and invalid cutoffs.
//!
//! Each case renders the bit-accurate frame on a small image, ray-marches the f64
//! reference and, where a single pixel is stiff, integrates it adaptively; it asserts no
//! panic, a finite non-negative reference, and the behaviour documented in
//! docs/shafts.md § Stiff and extreme cases (clamp and saturation counts, derived bounds, closed forms).
//!
//! Images are 65 × 49 (odd, so that the centre pixel (32, 24) looks exactly along the
//! view axis) unless stated; the whole file runs in a few seconds in the test profile.

mod common;

use std::f64::consts::PI;

use glare_pipeline::pipeline::shafts::frame::{render_frame, FrameResult, Prepared};
use glare_pipeline::pipeline::shafts::host::prepare_scene;
use glare_pipeline::pipeline::shafts::prepare::DEFAULT_EXPOSURE;
use glare_pipeline::reference::quadrature::{integrate_light, quadrature_pixel, QuadTol};
use glare_pipeline::reference::raymarch::{
    camera_ray, raymarch_image, raymarch_pixel, to_levels, LightEval,
};
use glare_pipeline::reference::shafts_model::S_MIN;
use glare_pipeline::report::metrics::{error_stats, ErrorStats};
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::{FScale, LightKind, LightMap, Scene};
use glare_pipeline::scene::geometry::SceneGeometry;
use glare_pipeline::scene::math::v3;

// ---------------------------------------------------------------- helpers

const W: u32 = 65;
const H: u32 = 49;
/// The centre pixel: its ray is exactly the view axis (x = y = 0 in NDC).
const CX: u32 = 32;
const CY: u32 = 24;
/// The ray-marched reference's samples per ray (as `render --reference`).
const SAMPLES: u32 = 180;
/// The usual frame-vs-reference tolerance (tests/shafts_pipeline.rs): RMS < 5 % of
/// full scale.
const RMS_TOL: f64 = 0.05 * 255.0;

/// The built-in Fig. 4 scene (one smooth spot seen from the side, no objects, m = 1)
/// at `w` × `h` with `n` planes. Camera at (0, 3, 14) looking along −z, near 0.5, far 40;
/// ρ = 0.025, κ = 0.8, K = 1; the spot at (−3, 10, 0), intensity 60, cutoff 20°.
/// The Fig. 4 room, pinned to the light and F-table scale these cases were measured
/// with (a smooth (1 − r²) spot of intensity 60, F scaled to the lit volume), so that
/// re-tuning the built-in does not move the documented behaviours.
fn fig4(w: u32, h: u32, n: u32) -> Scene {
    let mut s = builtin("fig4").unwrap();
    s.lights[0].intensity = 60.0;
    s.lights[0].light_map = Some(LightMap::Smooth { exponent: 1.0 });
    s.shafts.f_scale = FScale::LitVolume;
    s.image.width = w;
    s.image.height = h;
    s.shafts.planes = n;
    s
}

/// The Fig. 4 room with a point light instead of the spot.
fn point_scene(position: [f64; 3], intensity: f64, kappa: f64) -> Scene {
    let mut s = fig4(W, H, 30);
    let l = &mut s.lights[0];
    l.kind = LightKind::Point;
    l.light_map = None;
    l.position = position;
    l.intensity = intensity;
    s.medium.kappa = kappa;
    s
}

struct Run {
    scene: Scene,
    prepared: Prepared,
    geom: SceneGeometry,
    frame: FrameResult,
    /// Ray-marched reference, linear radiance (unclipped).
    reference: Vec<[f64; 3]>,
}

impl Run {
    fn new(scene: &Scene) -> Run {
        let (prepared, geom) = prepare_scene(scene, DEFAULT_EXPOSURE).unwrap();
        let frame = render_frame(&prepared).unwrap();
        let reference = raymarch_image(scene, &geom, SAMPLES);
        assert!(
            reference
                .iter()
                .flatten()
                .all(|c| c.is_finite() && *c >= 0.0),
            "reference has a NaN, an infinity or a negative value"
        );
        Run {
            scene: scene.clone(),
            prepared,
            geom,
            frame,
            reference,
        }
    }

    fn hw(&self) -> Vec<[f64; 3]> {
        self.frame.levels()
    }

    /// The reference in 8-bit levels, clipped to [0, 255] as the framebuffer is.
    fn ref_levels(&self) -> Vec<[f64; 3]> {
        self.reference
            .iter()
            .map(|v| to_levels(*v, DEFAULT_EXPOSURE))
            .collect()
    }

    fn stats(&self) -> ErrorStats {
        error_stats(&self.hw(), &self.ref_levels()).unwrap()
    }

    fn counter(&self, unit: &str) -> rtl_model::Counters {
        self.frame.counters.get(unit).cloned().unwrap_or_default()
    }

    fn index(&self, x: u32, y: u32) -> usize {
        (y * self.scene.image.width + x) as usize
    }

    /// The largest vertex colour code a sample plane can carry:
    /// round(255 · S · max t/r), S = F_max·h_ref·I·Δr·exposure/255 (frame.rs), and
    /// t/r = 1/cos of the view angle, largest at the image corners.
    fn max_plane_colour_code(&self) -> f64 {
        let s = &self.scene;
        let (r0, r1) = self.prepared.plane_range;
        let dr = (r1 - r0) / s.shafts.planes as f64;
        let l = &s.lights[0];
        let i = l.intensity * l.color.iter().cloned().fold(0.0, f64::max);
        let t = &self.frame.tables;
        let plane_scale = t.f_max * t.h_ref * i * dr * self.prepared.exposure / 255.0;
        let tan = (s.camera.fovy_deg.to_radians() / 2.0).tan();
        let aspect = s.image.width as f64 / s.image.height as f64;
        let t_over_r = (1.0 + tan * tan * (1.0 + aspect * aspect)).sqrt();
        (255.0 * plane_scale * t_over_r).round()
    }
}

fn all_zero(img: &[[f64; 3]]) -> bool {
    img.iter().flatten().all(|&c| c == 0.0)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-300)
}

use common::shafts::closed_form_point;

// ---------------------------------------------------------------- the light in view

/// A point light (intensity 4, κ = 0) at the centre of the view, 14 units in front of
/// the eye: the centre pixel's ray passes exactly through it.
fn light_in_view() -> Scene {
    point_scene([0.0, 3.0, 0.0], 4.0, 0.0)
}

#[test]
fn light_in_view_clamps_h_and_saturates_the_blend() {
    let run = Run::new(&light_in_view());
    let t = &run.frame.tables;
    let blend = run.counter("additive_blend");
    let st = run.stats();
    let (hw, rf) = (run.hw(), run.ref_levels());
    let c = run.index(CX, CY);
    let over = hw
        .iter()
        .zip(&rf)
        .map(|(a, b)| a[0] - b[0])
        .fold(f64::MIN, f64::max);
    let signed: f64 = hw.iter().zip(&rf).map(|(a, b)| a[0] - b[0]).sum::<f64>() / hw.len() as f64;
    println!(
        "light in view: s_near {:.4} h_ref {:.3e} h_clamped {} blend saturations {} | \
         centre hw {} ref {:.1} | mean {:.2} rms {:.2} max {:.1} | max(hw − ref) {over:.1} \
         mean(hw − ref) {signed:.2}",
        run.prepared.s_near,
        t.h_ref,
        t.h_clamped,
        blend.saturations,
        hw[c][0],
        run.reference[c][0] * DEFAULT_EXPOSURE,
        st.mean_abs,
        st.rms,
        st.max
    );
    // The host finds lit samples next to the light (s_near → 0), so h_ref is capped at
    // the ceiling where one plane at F_max adds full scale, and the texels nearer the
    // light than that clamp.
    assert!(run.prepared.s_near < 0.01, "s_near {}", run.prepared.s_near);
    assert!(t.h_clamped > 0);
    // Many planes near the light add up past full scale: the blend saturates (counted).
    assert!(blend.saturations > 0);
    assert_eq!(hw[c], [255.0; 3]);
    // Every pixel the frame saturates is saturated in the truth too (they surround the
    // light). The centre's ray-marched value is finite and far above full scale (it is
    // not converged: see the next test).
    let hw_sat = hw.iter().filter(|p| p[0] >= 255.0).count();
    let both = hw
        .iter()
        .zip(&rf)
        .filter(|(a, b)| a[0] >= 255.0 && b[0] >= 255.0)
        .count();
    assert!(hw_sat > 1 && both == hw_sat, "{both} of {hw_sat}");
    assert!(run.reference[c][0] * DEFAULT_EXPOSURE > 10.0 * 255.0);
    // Clamping only removes light: on average the frame is darker than the clipped
    // truth, and no pixel is brighter than it by more than the worst-case rounding of
    // 30 planes (½ level each).
    assert!(signed < 0.0, "mean(hw − ref) {signed}");
    assert!(over <= 15.0, "hw exceeds the reference by {over} levels");
    assert!(st.rms < RMS_TOL, "RMS {} levels", st.rms);
}

#[test]
fn ray_through_the_light_reference_is_clamped_and_finite() {
    let s = light_in_view();
    let geom = SceneGeometry::for_scene(&s, &mut |_, _| Ok(None)).unwrap();
    let (rho, k, i) = (s.medium.rho, s.medium.k, s.lights[0].intensity);
    let (t_star, t_end) = (14.0, s.camera.far);
    // The adaptive quadrature integrates h(max(s, S_MIN)): exactly
    // ρKI [22/S_MIN − 10/t* − 1/(T − t*)] for κ = 0 (F = 10K before the light, K after).
    let q = quadrature_pixel(&s, &geom, CX, CY, &QuadTol::rel(1e-10));
    let exact = rho * k * i * (22.0 / S_MIN - 10.0 / t_star - 1.0 / (t_end - t_star));
    assert!(q.value[0].is_finite());
    assert!(
        rel(q.scattered[0], exact) < 1e-7,
        "{} vs {exact}",
        q.scattered[0]
    );
    // The midpoint ray-marcher never samples closer than Δt/2 to the light here
    // (t* = 14 = 0.35·N·Δt, an integer multiple of Δt for N = 100, 200): its value is
    // finite but not converged: it grows like N, to leading order
    // ρKI · 11 · (π²/2) / Δt (Σ 1/(j + ½)² = π²/2 on each side, F = 10K and K).
    let v100 = raymarch_pixel(&s, &geom, CX, CY, 100)[0];
    let v200 = raymarch_pixel(&s, &geom, CX, CY, 200)[0];
    let lead = |n: f64| rho * k * i * 11.0 * PI * PI / 2.0 * n / t_end;
    println!(
        "through the light: quadrature {:.6e} (exact {exact:.6e}); raymarch N=100 {v100:.4e} \
         (leading {:.4e}), N=200 {v200:.4e}",
        q.scattered[0],
        lead(100.0)
    );
    assert!(v100.is_finite() && v200.is_finite());
    assert!(rel(v100, lead(100.0)) < 0.02, "{v100} vs {}", lead(100.0));
    assert!((v200 / v100 - 2.0).abs() < 0.02, "ratio {}", v200 / v100);
    assert!(v200 < exact);
}

#[test]
fn near_miss_quadrature_agrees_with_a_fine_ray_march() {
    // The light 10⁻³ above the centre ray: 1/s² is a Lorentzian of width 10⁻³ on a
    // 40-unit ray (stiff).
    let d = 1e-3;
    let s = point_scene([0.0, 3.0 + d, 0.0], 4.0, 0.0);
    let geom = SceneGeometry::for_scene(&s, &mut |_, _| Ok(None)).unwrap();
    let (rho, k, i) = (s.medium.rho, s.medium.k, s.lights[0].intensity);
    let exact = i * closed_form_point(rho, k, d, 14.0, s.camera.far);
    let q = quadrature_pixel(&s, &geom, CX, CY, &QuadTol::rel(1e-10));
    assert!(q.converged);
    assert!(
        rel(q.scattered[0], exact) < 1e-9,
        "{} vs {exact}",
        q.scattered[0]
    );
    // The midpoint rule on a Lorentzian of width d converges like exp(−2π d/Δt) once
    // Δt < d: with N = 400 000 (Δt = d/10) it agrees to far better than 10⁻⁶.
    let fine = raymarch_pixel(&s, &geom, CX, CY, 400_000)[0];
    // With the image's N = 180 (Δt = 222 d) the peak falls between samples.
    let coarse = raymarch_pixel(&s, &geom, CX, CY, SAMPLES)[0];
    println!(
        "near miss d = {d}: exact {exact:.9e} quadrature {:.9e} ({} evaluations) fine {fine:.9e} \
         coarse {coarse:.4e}",
        q.scattered[0], q.evaluations
    );
    assert!(
        rel(fine, q.scattered[0]) < 1e-6,
        "{fine} vs {}",
        q.scattered[0]
    );
    assert!(rel(coarse, exact) > 0.5, "coarse {coarse} vs {exact}");
}

// ---------------------------------------------------------------- ρκ

#[test]
fn rho_kappa_zero_matches_the_closed_form() {
    // A point light above the frame (where the Fig. 4 spot hangs), κ = 0: every pixel's
    // I_s has the closed form; the ray-marcher (180 samples, smooth integrand: the light
    // is ≥ 1.9 units from every ray) is within the midpoint rule's O(Δt²/d²) of it.
    let s = point_scene([-3.0, 10.0, 0.0], 4.0, 0.0);
    let run = Run::new(&s);
    let lp = v3(-3.0, 10.0, 0.0);
    let (rho, k, i) = (s.medium.rho, s.medium.k, s.lights[0].intensity);
    let mut worst: f64 = 0.0;
    for y in 0..H {
        for x in 0..W {
            let cr = camera_ray(&s, x as f64, y as f64);
            let w0 = lp - cr.ray.origin;
            let t0 = w0.dot(cr.ray.dir);
            let d = (w0 - cr.ray.dir * t0).length();
            let exact = i * closed_form_point(rho, k, d, t0, cr.t_far);
            worst = worst.max(rel(run.reference[run.index(x, y)][0], exact));
        }
    }
    let st = run.stats();
    println!(
        "ρκ = 0: worst ray-march vs closed form {worst:.2e}; frame mean {:.2} rms {:.2} max {:.1}",
        st.mean_abs, st.rms, st.max
    );
    assert!(worst < 1e-3, "{worst}");
    for (x, y) in [(CX, CY), (0, 0), (W - 1, H - 1)] {
        let q = quadrature_pixel(&s, &run.geom, x, y, &QuadTol::rel(1e-10));
        let cr = camera_ray(&s, x as f64, y as f64);
        let w0 = lp - cr.ray.origin;
        let t0 = w0.dot(cr.ray.dir);
        let d = (w0 - cr.ray.dir * t0).length();
        let exact = i * closed_form_point(rho, k, d, t0, cr.t_far);
        assert!(rel(q.scattered[0], exact) < 1e-9, "({x}, {y})");
    }
    assert!(st.rms < RMS_TOL, "RMS {}", st.rms);
}

#[test]
fn rho_kappa_tiny_equals_zero_within_the_derived_bound() {
    let mut s0 = fig4(W, H, 30);
    s0.medium.kappa = 0.0;
    let mut s6 = s0.clone();
    s6.medium.kappa = 1e-6 / s6.medium.rho;
    let (a, b) = (Run::new(&s0), Run::new(&s6));
    // Per sample, g(ρκ) = g(0)·exp(−ρκ(s + t)) and s + t ≤ 2t + |eye − light| ≤ 2T + D
    // along a ray, so 0 ≤ I(0) − I(ρκ) ≤ I(0)·(1 − exp(−ρκ(2T + D))), T ≤ far/cos.
    let d_el = (v3(0.0, 3.0, 14.0) - v3(-3.0, 10.0, 0.0)).length();
    let mut worst: f64 = 0.0;
    for (p, (r0, r6)) in a.reference.iter().zip(&b.reference).enumerate() {
        let (x, y) = (p as u32 % W, p as u32 / W);
        let t = camera_ray(&s0, x as f64, y as f64).t_far;
        let bound = 1.0 - (-1e-6 * (2.0 * t + d_el)).exp();
        let drop = r0[0] - r6[0];
        assert!(
            drop >= 0.0 && drop <= bound * r0[0] * (1.0 + 1e-9),
            "pixel {p}"
        );
        worst = worst.max(if r0[0] > 0.0 { drop / r0[0] } else { 0.0 });
    }
    // The hardware: every table entry and the plane scale change by a factor within
    // 10⁻⁴ of 1, so only values within 10⁻⁴ of a rounding boundary can move by one code.
    let (ha, hb) = (a.hw(), b.hw());
    let differ = ha.iter().zip(&hb).filter(|(x, y)| x != y).count();
    let dmax = ha
        .iter()
        .zip(&hb)
        .map(|(x, y)| (x[0] - y[0]).abs())
        .fold(0.0, f64::max);
    println!(
        "ρκ 1e-6 vs 0: worst reference drop {worst:.2e}; frames differ in {differ} pixels, \
         by at most {dmax} levels; h_clamped {} vs {}",
        a.frame.tables.h_clamped, b.frame.tables.h_clamped
    );
    assert!(differ * 100 <= ha.len(), "{differ} pixels differ");
    assert!(dmax <= 2.0, "{dmax}");
}

#[test]
fn rho_kappa_10_and_1000_extinguish_everything() {
    let base = Run::new(&{
        let mut s = fig4(W, H, 30);
        s.medium.kappa = 0.0;
        s
    });
    let d_el = (v3(0.0, 3.0, 14.0) - v3(-3.0, 10.0, 0.0)).length();
    for rk in [10.0, 1000.0] {
        let mut s = fig4(W, H, 30);
        s.medium.kappa = rk / s.medium.rho;
        let run = Run::new(&s);
        let rmax = run.reference.iter().flatten().cloned().fold(0.0, f64::max);
        println!(
            "ρκ = {rk}: h_ref {:.3e}, plane colour ≤ {} codes, reference max {rmax:.3e}",
            run.frame.tables.h_ref,
            run.max_plane_colour_code()
        );
        // Along any ray s + t ≥ |eye − light| = D (triangle inequality), so the truth is
        // at most exp(−ρκD) of the ρκ = 0 image (the same samples): 10⁻⁶⁹ at ρκ = 10,
        // and exp underflows to exactly 0 at ρκ = 1000.
        let bound = (-rk * d_el).exp();
        for (r, r0) in run.reference.iter().zip(&base.reference) {
            assert!(r[0] <= bound * r0[0] * (1.0 + 1e-9));
        }
        if rk == 1000.0 {
            assert!(all_zero(&run.reference));
            // h(s_near) underflows to 0: the tables are all zero (never 0/0).
            assert_eq!(run.frame.tables.h_ref, 0.0);
            assert!(run.frame.tables.h_texels.iter().all(|&t| t == 0));
        }
        // The plane scale S ∝ h_ref rounds to a zero vertex colour: every plane adds 0.
        assert_eq!(run.max_plane_colour_code(), 0.0);
        assert!(all_zero(&run.hw()));
        assert_eq!(run.counter("additive_blend").saturations, 0);
    }
}

// ---------------------------------------------------------------- n

#[test]
fn one_plane_renders_within_full_scale() {
    let one = Run::new(&fig4(W, H, 1));
    let thirty = Run::new(&fig4(W, H, 30));
    let (s1, s30) = (one.stats(), thirty.stats());
    println!(
        "n = 1: h_ref {:.3e} h_clamped {} rms {:.2} | n = 30: h_ref {:.3e} h_clamped {} rms {:.2}",
        one.frame.tables.h_ref,
        one.frame.tables.h_clamped,
        s1.rms,
        thirty.frame.tables.h_ref,
        thirty.frame.tables.h_clamped,
        s30.rms
    );
    // One plane spans the whole lit depth (Δr = r1 − r0): h_ref drops to the ceiling
    // where that plane at F_max adds full scale, so more texels clamp, and one plane on
    // an empty framebuffer cannot saturate.
    assert!(one.frame.tables.h_ref < thirty.frame.tables.h_ref);
    assert!(one.frame.tables.h_clamped > thirty.frame.tables.h_clamped);
    assert_eq!(one.counter("additive_blend").saturations, 0);
    assert!(one.hw().iter().any(|p| p[0] > 50.0));
    // One midpoint sample per ray is a coarse quadrature: the error exceeds n = 30's.
    assert!(s1.rms > 2.0 * s30.rms, "{} vs {}", s1.rms, s30.rms);
}

#[test]
fn five_thousand_planes_each_round_to_zero() {
    // 17 × 13 pixels and a 3 × 2 mesh per plane keep 5000 planes to about a second.
    let small = |n| {
        let mut s = fig4(17, 13, n);
        s.shafts.mesh = [3, 2];
        s
    };
    let many = Run::new(&small(5000));
    let thirty = Run::new(&small(30));
    let rmax = many.ref_levels().iter().map(|p| p[0]).fold(0.0, f64::max);
    let (sm, s30) = (many.stats(), thirty.stats());
    println!(
        "n = 5000: plane colour ≤ {} codes, frame max {}, reference max {rmax:.1}, rms {:.2} \
         (n = 30: rms {:.2}); blend fragments {}",
        many.max_plane_colour_code(),
        many.hw().iter().map(|p| p[0]).fold(0.0, f64::max),
        sm.rms,
        s30.rms,
        many.counter("additive_blend").pixels_in
    );
    // Δr = 10.1/5000: each plane's vertex colour S·t/r is at most 1 code, and F·h·J
    // stays below 128/255 in this scene, so every plane's modulated colour rounds to 0:
    // 5000 planes are drawn (and counted) but the frame stays black while the truth
    // peaks at ~90 levels. 8-bit per-plane quantisation loses everything.
    assert!(many.max_plane_colour_code() <= 1.0);
    assert_eq!(many.counter("additive_blend").pixels_in, 5000 * 17 * 13);
    assert!(all_zero(&many.hw()));
    assert!(rmax > 50.0);
    assert!(sm.rms > 3.0 * s30.rms, "{} vs {}", sm.rms, s30.rms);
}

// ---------------------------------------------------------------- light behind the camera

#[test]
fn light_behind_the_camera() {
    // Three units behind the eye, pointing forward along the view: the cone fills the
    // view from the eye on. α ≈ 180° (back-scatter), F ≈ K.
    let mut s = fig4(W, H, 30);
    s.lights[0].position = [0.0, 3.3, 17.0];
    s.lights[0].direction = [0.0, -0.05, -1.0];
    let run = Run::new(&s);
    // The planes start at the near plane; the reference integrates from the eye. The
    // slab [0, near/cos] in front of the eye is the brightest part of the path here
    // (s is smallest), so subtract it (adaptive quadrature per pixel) before comparing.
    let lights = LightEval::all(&s, &run.geom);
    let fwd = v3(0.0, 0.0, -1.0);
    let mut beyond_near = Vec::with_capacity(run.reference.len());
    let mut slab_mean = 0.0;
    for y in 0..H {
        for x in 0..W {
            let cr = camera_ray(&s, x as f64, y as f64);
            let t_near = s.camera.near / cr.ray.dir.dot(fwd);
            let slab = integrate_light(
                &lights[0],
                &s.medium,
                &run.geom,
                &cr.ray,
                t_near,
                &QuadTol::rel(1e-8),
            );
            assert!(slab.converged && slab.value.is_finite() && slab.value >= 0.0);
            let full = run.reference[run.index(x, y)];
            slab_mean += slab.value * DEFAULT_EXPOSURE / run.reference.len() as f64;
            beyond_near.push(to_levels(full.map(|c| c - slab.value), DEFAULT_EXPOSURE));
        }
    }
    let st = run.stats();
    let near = error_stats(&run.hw(), &beyond_near).unwrap();
    println!(
        "behind, forward: vs reference from the eye mean {:.2} rms {:.2}; from the near \
         plane mean {:.2} rms {:.2} max {:.1}; slab mean {slab_mean:.2} levels",
        st.mean_abs, st.rms, near.mean_abs, near.rms, near.max
    );
    assert!(near.rms < RMS_TOL, "RMS {}", near.rms);
    // The slab accounts for most of the gap to the reference from the eye.
    assert!(slab_mean > 0.5 * st.mean_abs);
    assert!(st.mean_abs > 2.0 * near.mean_abs);

    // Pointing away: nothing in front of the eye is lit. The host finds no lit sample
    // and draws the planes over a token interval at the near plane; every plane fragment
    // is behind the projector (q ≤ 0: counted as a projective underflow) and gets J = 0.
    let mut s = fig4(W, H, 30);
    s.lights[0].position = [0.0, 3.3, 17.0];
    s.lights[0].direction = [0.0, 0.0, 1.0];
    let run = Run::new(&s);
    let proj = run.counter("projective_texcoord");
    assert!(proj.pixels_in > 0);
    assert_eq!(proj.underflows, proj.pixels_in);
    assert!(all_zero(&run.hw()));
    assert!(all_zero(&run.reference));
}

// ---------------------------------------------------------------- intensity

#[test]
fn intensity_zero_gives_a_black_frame() {
    let mut s = fig4(W, H, 30);
    s.lights[0].intensity = 0.0;
    let run = Run::new(&s);
    assert!(all_zero(&run.hw()));
    assert!(all_zero(&run.reference));
    // No light: the plane passes are skipped, nothing is blended or saturates.
    assert_eq!(run.counter("additive_blend").pixels_in, 0);
    assert_eq!(run.counter("additive_blend").saturations, 0);
    assert_eq!(run.frame.tables.h_ref, 0.0);
}

#[test]
fn intensity_huge_saturates_the_lit_pixels() {
    let base = Run::new(&fig4(W, H, 30));
    let mut s = fig4(W, H, 30);
    s.lights[0].intensity = 1e6;
    let run = Run::new(&s);
    let t = &run.frame.tables;
    let (hw, rf) = (run.hw(), run.ref_levels());
    let rmax = run.reference.iter().flatten().cloned().fold(0.0, f64::max);
    let ref_sat = rf.iter().filter(|p| p[0] >= 255.0).count();
    let hw_sat = hw.iter().filter(|p| p[0] >= 255.0).count();
    let both = hw
        .iter()
        .zip(&rf)
        .filter(|(a, b)| a[0] >= 255.0 && b[0] >= 255.0)
        .count();
    let over = hw
        .iter()
        .zip(&rf)
        .map(|(a, b)| a[0] - b[0])
        .fold(f64::MIN, f64::max);
    println!(
        "I = 1e6: h_ref {:.3e} h_clamped {} of {} blend saturations {} | reference max \
         {rmax:.1} (radiance) saturated px {ref_sat}, frame saturated px {hw_sat} (both \
         {both}) max(hw − ref) {over}",
        t.h_ref,
        t.h_clamped,
        t.h_texels.len(),
        run.counter("additive_blend").saturations
    );
    // The truth is linear in I and unclipped.
    let k = 1e6 / base.scene.lights[0].intensity;
    for (a, b) in run.reference.iter().zip(&base.reference) {
        assert!((a[0] - k * b[0]).abs() <= 1e-12 * a[0]);
    }
    assert!(rmax > 1.0);
    // h_ref is capped so that one plane at F_max adds exactly full scale: every h texel
    // clamps (h becomes a constant 1), and the planes' sum saturates the blend.
    assert_eq!(t.h_clamped as usize, t.h_texels.len());
    assert!(run.counter("additive_blend").saturations > 0);
    // Every pixel the frame saturates is saturated in the truth; the frame is never
    // brighter than the clipped truth by more than a level of rounding; at least half the truth's saturated pixels are
    // at full scale (the rest lie at the cone's rim, where a ray crosses one or two
    // planes with a small light-map value).
    assert_eq!(both, hw_sat);
    assert!(over <= 1.0, "{over}");
    assert!(2 * hw_sat >= ref_sat, "{hw_sat} of {ref_sat}");
}

// ---------------------------------------------------------------- degenerate cones

#[test]
fn tiny_and_wide_cones() {
    // 10⁻⁴° and 10⁻²° seen from the side: no pixel ray meets a cone that thin (the truth
    // is exactly 0). The light's projective coordinates exceed the interpolator's
    // s16.16 range off-axis (counted saturations); fragments whose (u, v) fall outside
    // the light's square get J = 0 (border colour 0), so the frame is black too.
    for c in [1e-4, 1e-2] {
        let mut s = fig4(W, H, 30);
        s.lights[0].cutoff_deg = c;
        let run = Run::new(&s);
        println!(
            "cutoff {c}°: interpolator saturations {}",
            run.counter("polygon_interpolator").saturations
        );
        // The ray-march is clipped to the cone, so a ray that grazes the needle near
        // its apex finds it: the chord is at most 2·s·tan(cutoff), and the truth stays
        // below a hundredth of a level everywhere (it rounds to the black frame).
        let rmax = run.reference.iter().map(|p| p[0]).fold(0.0, f64::max);
        println!("cutoff {c}°: reference max {rmax:e} levels");
        assert!(rmax < 0.01, "cutoff {c}: reference max {rmax}");
        assert!(run.counter("polygon_interpolator").saturations > 0);
        assert!(all_zero(&run.hw()), "cutoff {c}");
    }

    // The eye inside a 10⁻⁴° cone pointing at it: only the centre ray is inside. Its
    // truth (κ = 0) is ∫₀^t* ρ·10K·I/max(s, S_MIN)² dt = 10ρKI(2/S_MIN − 1/t*) (the
    // last S_MIN before the light is at the clamp: 1/S_MIN more).
    let mut s = fig4(W, H, 30);
    s.medium.kappa = 0.0;
    s.lights[0].position = [0.0, 3.0, 0.0];
    s.lights[0].direction = [0.0, 0.0, 1.0];
    s.lights[0].cutoff_deg = 1e-4;
    s.lights[0].intensity = 4.0;
    let run = Run::new(&s);
    let q = quadrature_pixel(&s, &run.geom, CX, CY, &QuadTol::rel(1e-10));
    let exact = 10.0 * s.medium.rho * s.medium.k * 4.0 * (2.0 / S_MIN - 1.0 / 14.0);
    assert!(
        rel(q.scattered[0], exact) < 1e-7,
        "{} vs {exact}",
        q.scattered[0]
    );
    let (hw, rf) = (run.hw(), run.ref_levels());
    let c = run.index(CX, CY);
    println!(
        "eye in a 1e-4° cone: centre frame {} reference {:.3e} levels; interpolator \
         saturations {}",
        hw[c][0],
        run.reference[c][0] * DEFAULT_EXPOSURE,
        run.counter("polygon_interpolator").saturations
    );
    assert!(rf[c][0] >= 255.0);
    assert!(run.counter("polygon_interpolator").saturations > 0);
    // Documented loss: the saturated light coordinates misplace the sub-pixel cone, so
    // the frame does not reach the truth's full scale at the centre; it never lights a
    // pixel the truth leaves dark.
    assert!(hw[c][0] < 255.0);
    for (a, b) in hw.iter().zip(&rf) {
        assert!(b[0] > 0.0 || a[0] == 0.0);
    }

    // Near the largest valid cutoff (< 90°): the light's frustum is capped at 179°, the
    // cone covers the whole view; the frame is within the usual tolerance.
    for c in [89.0, 89.999] {
        let mut s = fig4(W, H, 30);
        s.lights[0].cutoff_deg = c;
        let run = Run::new(&s);
        let st = run.stats();
        println!(
            "cutoff {c}°: mean {:.2} rms {:.2} max {:.1}",
            st.mean_abs, st.rms, st.max
        );
        assert!(st.rms < RMS_TOL, "cutoff {c}: RMS {}", st.rms);
    }

    // A uniform spot (no light map): its texture is the cone's disc, which reaches the
    // edge texels at the mid-edges. Outside the light's square the border colour 0
    // applies, so nothing outside the cone is lit (clamp-to-edge used to smear those
    // texels over the half-space in front of the light).
    let mut s = fig4(W, H, 30);
    s.lights[0].light_map = None;
    let run = Run::new(&s);
    let (hw, rf) = (run.hw(), run.ref_levels());
    let outside: Vec<f64> = hw
        .iter()
        .zip(&run.reference)
        .filter(|(_, r)| r[0] == 0.0)
        .map(|(a, _)| a[0])
        .collect();
    let lit_outside = outside.iter().filter(|&&v| v > 0.0).count();
    let st = error_stats(&hw, &rf).unwrap();
    println!(
        "uniform spot: {lit_outside} of {} unlit pixels lit, max {}; rms {:.2}",
        outside.len(),
        outside.iter().cloned().fold(0.0, f64::max),
        st.rms
    );
    assert!(lit_outside * 200 <= outside.len());
    assert!(outside.iter().all(|&v| v <= 2.0));
    assert!(st.rms < RMS_TOL);
}

#[test]
fn invalid_cutoffs_are_errors_naming_the_field() {
    for c in [0.0, -1.0, 90.0, 120.0, f64::NAN, f64::INFINITY, -0.0] {
        let mut s = fig4(W, H, 30);
        s.lights[0].cutoff_deg = c;
        let e = prepare_scene(&s, DEFAULT_EXPOSURE).unwrap_err();
        assert_eq!(e.field(), "lights[0].cutoff_deg", "cutoff {c}: {e}");
    }
    // A point light ignores the cutoff, but it must still be a number.
    let mut s = point_scene([0.0, 3.0, 0.0], 1.0, 0.0);
    s.lights[0].cutoff_deg = 0.0;
    assert!(prepare_scene(&s, DEFAULT_EXPOSURE).is_ok());
    s.lights[0].cutoff_deg = f64::NAN;
    let e = prepare_scene(&s, DEFAULT_EXPOSURE).unwrap_err();
    assert_eq!(e.field(), "lights[0].cutoff_deg");
}

#[test]
fn point_light_with_occluders_is_not_cut_to_a_cone() {
    // The border colour belongs to a spot's light map: a point light has none, so its
    // light is not cut to the square frustum the shadow map uses (2 × the unused
    // cutoff). Fig. 6 (sphere and floor, m = 6) with its spot turned into a point light.
    let mut s = builtin("fig6").unwrap();
    s.image.width = W;
    s.image.height = H;
    s.shafts.shadow_resolution = 128;
    s.lights[0].kind = LightKind::Point;
    s.lights[0].light_map = None;
    s.lights[0].intensity = 5.0;
    let run = Run::new(&s);
    let st = run.stats();
    let (hw, rf) = (run.hw(), run.ref_levels());
    let dark = hw
        .iter()
        .zip(&rf)
        .filter(|(a, b)| a[0] == 0.0 && b[0] >= 5.0)
        .count();
    println!(
        "point light with occluders: mean {:.2} rms {:.2} max {:.1}; {dark} pixels dark \
         where the truth has ≥ 5 levels",
        st.mean_abs, st.rms, st.max
    );
    assert_eq!(dark, 0);
    assert!(st.rms < RMS_TOL, "RMS {}", st.rms);
}
