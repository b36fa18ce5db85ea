//! The shafts pipeline end to end on small frames: determinism whatever the thread
//! count, agreement with the ray-marched reference, elaboration.

use glare_pipeline::chip::{predict, GpuModel};
use glare_pipeline::pipeline::shafts::frame::render_frame;
use glare_pipeline::pipeline::shafts::host::prepare_scene;
use glare_pipeline::pipeline::shafts::prepare::DEFAULT_EXPOSURE;
use glare_pipeline::reference::raymarch::{raymarch_image, to_levels};
use glare_pipeline::report::metrics::error_stats;
use glare_pipeline::scene::builtin::builtin;
use glare_pipeline::scene::format::{LightKind, Scene};

fn small(name: &str, planes: u32, subplanes: u32) -> Scene {
    let mut s = builtin(name).unwrap();
    s.image.width = 120;
    s.image.height = 80;
    s.shafts.planes = planes;
    s.shafts.subplanes = subplanes;
    s.shafts.shadow_resolution = 128;
    s
}

fn frame(s: &Scene) -> glare_pipeline::pipeline::shafts::frame::FrameResult {
    let (p, _) = prepare_scene(s, DEFAULT_EXPOSURE).unwrap();
    render_frame(&p).unwrap()
}

#[test]
fn same_bytes_on_one_and_two_threads() {
    // m = 5: the sub-planes' H·I_l run in batches of 4 (one full, one partial).
    let s = small("fig6", 6, 5);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let a = one.install(|| frame(&s));
    let b = two.install(|| frame(&s));
    assert_eq!(a.fb, b.fb);
    assert_eq!(a.counters, b.counters);
    assert_eq!(format!("{:?}", a.passes), format!("{:?}", b.passes));
}

#[test]
fn close_to_the_ray_marched_reference() {
    let s = small("fig6", 30, 6);
    let r = frame(&s);
    let (p, geom) = prepare_scene(&s, DEFAULT_EXPOSURE).unwrap();
    let _ = p;
    let reference: Vec<[f64; 3]> = raymarch_image(&s, &geom, 180)
        .into_iter()
        .map(|v| to_levels(v, DEFAULT_EXPOSURE))
        .collect();
    let st = error_stats(&r.levels(), &reference).unwrap();
    println!(
        "mean |Δ| {:.3} levels, RMS {:.3} levels, max {:.1}",
        st.mean_abs, st.rms, st.max
    );
    // The 8-bit pipeline with 30 planes and 6 sub-planes: a few levels of RMS at most
    // (the full-size frame measures 0.7 % of full scale; reproduce shafts-vs-raymarch).
    assert!(st.rms < 0.05 * 255.0, "RMS {} levels", st.rms);
    // And the image is not black: shafts and the lit floor are there.
    let lit = r.levels().iter().filter(|p| p[0] > 8.0).count();
    assert!(lit > 120 * 80 / 10, "{lit} lit pixels");
}

#[test]
fn elaboration_leaves_out_what_the_scene_does_not_use() {
    // fig4: no objects → no shadow map, no depth buffer; m = 1 → no sub-plane path.
    let s = small("fig4", 4, 1);
    let r = frame(&s);
    let left: Vec<&str> = r
        .elaboration
        .iter()
        .filter(|e| e.left_out.is_some())
        .map(|e| e.name.as_str())
        .collect();
    assert!(
        left.iter()
            .any(|n| n.starts_with("shadow_compare (shadow map)")),
        "{left:?}"
    );
    assert!(
        left.iter()
            .any(|n| n.starts_with("shadow_compare (depth buffer)")),
        "{left:?}"
    );
    assert!(left.iter().any(|n| n.contains("J buffer")), "{left:?}");
    assert!(!r.counters.contains_key("shadow_compare (shadow map)"));
    assert!(!r.counters.contains_key("additive_blend (J buffer)"));
    let saved: f64 = r.elaboration.iter().map(|e| e.gates_saved).sum();
    assert!(saved > 0.0);

    // A point light has no light map: no projective unit, no light-map sampler.
    let mut s = small("fig4", 4, 1);
    s.lights[0].kind = LightKind::Point;
    s.lights[0].light_map = None;
    let r = frame(&s);
    assert!(!r.counters.contains_key("projective_texcoord"));
    assert!(!r.counters.contains_key("texture_sampler (light map)"));
}

#[test]
fn predicted_time_grows_with_planes_and_subplanes() {
    let t = |n, m| {
        let p = predict(
            &GpuModel::geforce2_gts(),
            &frame(&small("fig6", n, m)).passes,
        );
        let get = |k: &str| p.by_kind.get(k).copied().unwrap_or(0.0);
        (get("planes"), get("sub_planes"), p.seconds)
    };
    let (a, b, c, d) = (t(5, 1), t(10, 1), t(10, 3), t(10, 6));
    // Plane time is proportional to n; sub-planes appear with m > 1 and cost n·m
    // full-screen passes.
    assert!((b.0 / a.0 - 2.0).abs() < 0.05, "{a:?} {b:?}");
    assert_eq!(a.1, 0.0);
    assert!((d.1 / c.1 - 2.0).abs() < 0.05, "{c:?} {d:?}");
    assert!(c.1 > 0.0 && c.2 > b.2 && d.2 > c.2, "{b:?} {c:?} {d:?}");
    // With m = 1 a plane needs F, h, the light map and the shadow map: 4 textures, two
    // hardware passes on a 2-texture part; with m > 1 it needs F, h and J: still two.
    // A sub-plane needs the light map and the shadow map: one pass, so 3·n sub-planes
    // cost more than the n two-pass planes but less than 3× as much.
    assert!(c.1 > b.0 && c.1 < 3.0 * b.0, "{b:?} {c:?}");
}
