//! The 2D-slice elaboration (src/pipeline/envmap/slice.rs) and the frame-time model
//! (src/pipeline/envmap/timing.rs). Small cases: the 64 × 32 pattern, an s = 16 map
//! from `quick_map`, 64 × 64 images.

use std::sync::OnceLock;

use glare_pipeline::chip::GpuModel;
use glare_pipeline::pipeline::envmap::render::{
    quick_map, render_frame, render_object_with, Image, LambdaSpec, Lookup, Object, RenderOptions,
};
use glare_pipeline::pipeline::envmap::slice::{default_face_side, slice_from_map};
use glare_pipeline::pipeline::envmap::timing::predict_frame;
use glare_pipeline::pipeline::envmap::voxmap::VoxelMap;
use glare_pipeline::scene::envmap::EnvMap;

const SIZE: (u32, u32) = (64, 64);
const S: u32 = 16;

fn pattern() -> &'static (EnvMap, VoxelMap) {
    static P: OnceLock<(EnvMap, VoxelMap)> = OnceLock::new();
    P.get_or_init(|| {
        let env = EnvMap::pattern(64, 32);
        let map = quick_map(&env, S).unwrap();
        (env, map)
    })
}

fn opt(lookup: Lookup) -> RenderOptions {
    RenderOptions {
        lookup,
        ..RenderOptions::default()
    }
}

/// Mean and largest |a − b| over the object pixels (all channels).
fn diff(a: &Image, b: &Image) -> (f64, u8) {
    assert_eq!(a.mask, b.mask);
    let (mut sum, mut n, mut max) = (0.0, 0usize, 0u8);
    for k in 0..a.pixels.len() {
        if a.mask[k] {
            for c in 0..3 {
                let d = a.pixels[k][c].abs_diff(b.pixels[k][c]);
                sum += d as f64;
                n += 1;
                max = max.max(d);
            }
        }
    }
    (sum / n.max(1) as f64, max)
}

#[test]
fn uniform_lambda_elaborates_the_2d_slice_and_leaves_out_the_3d_sampler() {
    let (env, map) = pattern();
    for object in [Object::Sphere, Object::Teapot] {
        let (_, f) = render_frame(
            env,
            map,
            object,
            LambdaSpec::Uniform(0.5),
            SIZE,
            &opt(Lookup::Auto),
        )
        .unwrap();
        let el = &f.elaboration;
        assert!(el.slice_2d);
        assert_eq!(f.texels_per_lookup, 4);
        // The 2D sampler and the cube_map_address unit elaborated, the 3D sampler left
        // out, the reflection unit (which feeds both paths) elaborated.
        assert_eq!(el.units.len(), 4);
        assert_eq!(el.units[0].name, "texture_sampler (2D cube map)");
        assert!(el.units[0].left_out.is_none() && el.units[0].summary.is_some());
        assert_eq!(el.units[1].name, "cube_map_address");
        assert!(el.units[1].left_out.is_none() && el.units[1].summary.is_some());
        assert_eq!(el.units[2].name, "texture_sampler (3D map)");
        assert!(el.units[2].left_out.is_some() && el.units[2].summary.is_none());
        assert!(el.units[2].gates_saved > 0.0);
        assert_eq!(el.units[3].name, "reflection_vector");
        assert!(el.units[3].left_out.is_none());
        // s = 16: F = 32, a 32 × 192 × 3 cube map against 16³ × 3 bytes: at this small
        // s the cube map is the larger (6F² = 24s² > s³ for s < 24), nothing saved.
        let cube_bytes = 6 * 32 * 32 * 3;
        assert_eq!(el.texture_bytes, cube_bytes);
        assert_eq!(el.texture_bytes_saved, 0);
        let s2 = el.units[0].summary.as_ref().unwrap();
        assert_eq!(s2.ram_bits, cube_bytes * 8);
        // The saving counts the cube unit's gates against the 3D sampler's.
        let cube_gates = el.units[1].summary.as_ref().unwrap().gates_nand2;
        assert!(
            (el.gates_saved - (el.units[2].gates_saved - s2.gates_nand2 - cube_gates)).abs() < 1e-6
        );
        println!(
            "{}: gates saved {:.0} (3D sampler {:.0} − 2D sampler {:.0} − cube_map_address {cube_gates:.0})",
            object.name(),
            el.gates_saved,
            el.units[2].gates_saved,
            s2.gates_nand2
        );
        // The stacked texture is F wide, a power of two: the address (y·F + x) is a
        // concatenation although its 6F rows are not a power of two, so the 2D
        // sampler's cost has no address multiplier or base adder.
        assert!(
            !s2.breakdown.iter().any(|(p, _)| p.starts_with("address")),
            "{:?}",
            s2.breakdown
        );
        // II 2 → 1: one clock saved per lookup.
        assert_eq!(el.units[2].cycles_saved, f.shaded);
        let table = glare_pipeline::report::table::elaboration_table(&el.units);
        assert!(table.contains("left out"), "{table}");
    }
}

#[test]
fn nonuniform_lambda_and_the_default_use_the_3d_map() {
    let (env, map) = pattern();
    for (lambda, lookup) in [
        (LambdaSpec::NonUniform, Lookup::Auto),
        (LambdaSpec::NonUniform, Lookup::Voxel3D),
        (LambdaSpec::Uniform(0.5), Lookup::Voxel3D),
    ] {
        let (_, f) = render_frame(env, map, Object::Sphere, lambda, SIZE, &opt(lookup)).unwrap();
        let el = &f.elaboration;
        assert!(!el.slice_2d, "{lambda:?} {lookup:?}");
        assert_eq!(f.texels_per_lookup, 8);
        // The 3D sampler and the reflection unit that feeds it; the cube-map address
        // unit left out.
        assert_eq!(el.units.len(), 3);
        assert_eq!(el.units[0].name, "texture_sampler (3D map)");
        assert_eq!(el.units[1].name, "cube_map_address");
        assert!(el.units[1].left_out.is_some() && el.units[1].summary.is_none());
        assert!(el.units[1].gates_saved > 0.0);
        assert_eq!(el.units[2].name, "reflection_vector");
        assert!(el.units[0].left_out.is_none() && el.units[2].left_out.is_none());
        assert_eq!(el.texture_bytes, map.bytes());
        assert_eq!(el.texture_bytes_saved, 0);
    }
    assert_eq!(RenderOptions::default().lookup, Lookup::Voxel3D);
}

/// The 2D render against the 3D render of the same map, both 8-bit: the slice is the
/// map's trilinear value at texel centres of a 4s × 2s equirectangular grid, rounded to
/// 8 bits (≤ ½ level), then bilinear; the 3D render is trilinear directly. They differ
/// by the rounding and by re-interpolating the trilinear function between slice texels.
/// Measured at s = 16 (64 × 64): mean |Δ| 0.17–0.25, max 18 (sphere rim, λ = 1); the
/// truth errors differ by ≤ 0.08. The bounds (mean ≤ 0.5, max ≤ 24, ≤ 0.25) are
/// measured margins, not derived.
#[test]
fn the_2d_render_is_close_to_the_3d_render() {
    let (env, map) = pattern();
    for object in [Object::Sphere, Object::Teapot] {
        for l in [1.0, 0.5, 0.25] {
            let lambda = LambdaSpec::Uniform(l);
            let (img3, truth, st3) =
                render_object_with(env, map, object, lambda, SIZE, &opt(Lookup::Voxel3D)).unwrap();
            let (img2, _, st2) =
                render_object_with(env, map, object, lambda, SIZE, &opt(Lookup::Auto)).unwrap();
            assert!(st2.frame.elaboration.slice_2d);
            let (mean, max) = diff(&img2, &img3);
            let m3 = st3.cos_phi.mean.iter().sum::<f64>() / 3.0;
            let m2 = st2.cos_phi.mean.iter().sum::<f64>() / 3.0;
            println!(
                "{} λ={l}: 2D vs 3D mean |Δ| {mean:.3}, max {max}; vs truth 3D {m3:.3}, 2D {m2:.3}",
                object.name()
            );
            assert_eq!(img2.mask, truth.cos_phi.mask);
            assert!(mean <= 0.5, "mean {mean}");
            assert!(max <= 24, "max {max}");
            assert!((m2 - m3).abs() <= 0.25, "truth errors {m2} vs {m3}");
        }
    }
}

#[test]
fn slice_at_lambda_zero_is_the_centre_and_errors_name_the_field() {
    let (_, map) = pattern();
    let sl = slice_from_map(map, 0.0, 16).unwrap();
    let first = sl.data()[0];
    assert!(sl.data().iter().all(|&t| t == first));
    assert_eq!((sl.width(), sl.height()), (16, 96));
    // F = the smallest power of two ≥ 4s/π, capped at 512.
    assert_eq!(default_face_side(S), 32);
    assert_eq!(default_face_side(128), 256);
    assert_eq!(default_face_side(100), 128);
    assert_eq!(default_face_side(4096), 512);
    for l in [f64::NAN, f64::INFINITY, -0.1, 1.5] {
        let e = slice_from_map(map, l, 16).unwrap_err();
        assert_eq!(e.field(), "envmap_slice.lambda");
    }
    for f in [0, 1, 24, 1024] {
        let e = slice_from_map(map, 0.5, f).unwrap_err();
        assert_eq!(e.field(), "envmap_slice.size");
    }
}

#[test]
fn geforce3_prediction_is_under_a_60_fps_frame_and_scales() {
    let (env, map) = pattern();
    let gpu = GpuModel::geforce3();
    assert_eq!(gpu.textures_per_pass, 4);
    let (_, f3) = render_frame(
        env,
        map,
        Object::Sphere,
        LambdaSpec::NonUniform,
        (160, 120),
        &opt(Lookup::Voxel3D),
    )
    .unwrap();
    let (_, f2) = render_frame(
        env,
        map,
        Object::Sphere,
        LambdaSpec::Uniform(0.5),
        (160, 120),
        &opt(Lookup::Auto),
    )
    .unwrap();
    let (p3, p2) = (predict_frame(&gpu, &f3), predict_frame(&gpu, &f2));
    assert!(p3.seconds.is_finite() && p3.seconds > 0.0);
    assert!(p3.seconds < 1.0 / 60.0);
    // Same fragments, half the texels: the 2D slice is not slower.
    assert_eq!(f3.fragments, f2.fragments);
    assert!(p2.seconds <= p3.seconds);
    assert!(p2.bytes < p3.bytes);
    // 16× the pixels and fragments: more time, still well under 17 ms at 640 × 480.
    let mut big = f3.clone();
    big.width *= 4;
    big.height *= 4;
    big.fragments *= 16;
    big.background_pixels *= 16;
    let pb = predict_frame(&gpu, &big);
    assert!(pb.seconds > p3.seconds && pb.seconds < 1.0 / 60.0);
    // A slower card is slower.
    let slow = GpuModel {
        bytes_per_second: gpu.bytes_per_second / 4.0,
        clock_hz: gpu.clock_hz / 4.0,
        ..gpu
    };
    assert!(predict_frame(&slow, &f3).seconds > p3.seconds);
    // A roughness texture adds a bilinear sample per fragment: 12 texels take 2
    // clocks on 2 TMUs instead of 1, and 4 one-byte texels more per fragment.
    let mut rough = f3.clone();
    rough.roughness_texels_per_lookup = 4;
    let pr = predict_frame(&gpu, &rough);
    assert!((pr.object_fill_seconds - 2.0 * p3.object_fill_seconds).abs() < 1e-15);
    let extra = rough.fragments as f64 * 4.0 * (1.0 - gpu.texture_cache_hit);
    assert!((pr.bytes - p3.bytes - extra).abs() < 1e-6 * pr.bytes);
    assert!(pr.seconds > p3.seconds);
}

/// The 2D path through the units (reflection_vector → cube_map_address → 2D sampler)
/// against the HostF64 comparison path (the f64 r through the cube_map_address twin),
/// both on the same cube map. They differ by the reflection unit's and the cube unit's
/// coordinate errors (≤ 0.0556 texel in the 3D map's texels at s = 128, ≤ 0.0244 texel
/// of a 256² face; both are derived bounds in docs/units.md) seen through the bilinear
/// sampler, and, near a face edge, by a different face choice. The direction has
/// length λ·s/2 texels, so the fixed s16.8 rounding of the reflection unit's words
/// weighs more at small λ. Measured at s = 16 (64 × 64): mean |Δ| 0.009–0.045 levels
/// (largest at λ = 0.25), max 1; the assertion (mean ≤ 0.1, max ≤ 2) is a measured
/// margin, not a derived bound.
#[test]
fn the_2d_unit_path_matches_the_host_f64_cube_path() {
    use glare_pipeline::pipeline::envmap::render::Reflection;
    let (env, map) = pattern();
    for object in [Object::Sphere, Object::Teapot] {
        for l in [1.0, 0.5, 0.25] {
            let lambda = LambdaSpec::Uniform(l);
            let (a, _, sa) =
                render_object_with(env, map, object, lambda, SIZE, &opt(Lookup::Auto)).unwrap();
            let host = RenderOptions {
                reflection: Reflection::HostF64,
                ..opt(Lookup::Auto)
            };
            let (b, _, sb) = render_object_with(env, map, object, lambda, SIZE, &host).unwrap();
            assert!(sa.counters.contains_key("cube_map_address"));
            assert!(!sb.counters.contains_key("cube_map_address"));
            let el = &sb.frame.elaboration;
            assert_eq!(el.units[1].name, "cube_map_address");
            assert!(el.units[1].left_out.is_some());
            assert_eq!(el.gates_saved, sa.frame.elaboration.gates_saved);
            let (mean, max) = diff(&a, &b);
            println!(
                "{} λ={l}: 2D unit vs HostF64 cube path mean |Δ| {mean:.4}, max {max}",
                object.name()
            );
            assert!(mean <= 0.1, "mean {mean}");
            assert!(max <= 2, "max {max}");
        }
    }
}
