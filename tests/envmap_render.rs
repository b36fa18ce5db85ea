//! The multi-scale environment map renderer (src/pipeline/envmap/render.rs): objects
//! drawn through the polygon interpolator and the 3D texture sampler against the Phong
//! ground truth. Small cases: 64 × 32 environments, s = 16 maps from `quick_map`,
//! 64 × 64 images. `cargo test --test envmap_render -- --ignored --nocapture` writes
//! the look-at PNGs to the temp directory.

use std::sync::OnceLock;

use glare_pipeline::pipeline::envmap::render::{
    quick_map, render_object, render_object_with, Background, Image, LambdaSpec, Object,
    Reflection, RenderOptions,
};
use glare_pipeline::pipeline::envmap::table5::{table5_rows, Table5Row};
use glare_pipeline::pipeline::envmap::voxmap::VoxelMap;
use glare_pipeline::pipeline::shafts::view::CameraView;
use glare_pipeline::scene::envmap::EnvMap;
use glare_pipeline::scene::format::ImageSize;

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

fn mean3(v: [f64; 3]) -> f64 {
    (v[0] + v[1] + v[2]) / 3.0
}

#[test]
fn constant_environment_renders_the_constant() {
    let env = EnvMap::constant(64, 32, [0.3, 0.6, 0.9]).unwrap();
    let want = env.to_levels(env.auto_exposure()).unwrap()[0];
    assert_eq!(want, [85, 170, 255]);
    let map = quick_map(&env, S).unwrap();
    for (object, lambda) in [
        (Object::Sphere, LambdaSpec::Uniform(1.0)),
        (Object::Sphere, LambdaSpec::Uniform(0.25)),
        (Object::Sphere, LambdaSpec::NonUniform),
        (Object::Teapot, LambdaSpec::NonUniform),
    ] {
        let (img, truth, st) = render_object(&env, &map, object, lambda, SIZE).unwrap();
        assert!(img.coverage() > 300, "{object:?}: {} px", img.coverage());
        // Every voxel holds the constant's code (normalised weights), and trilinear
        // filtering of equal codes returns the code exactly (weights sum to W³).
        for k in 0..img.pixels.len() {
            if img.mask[k] {
                assert_eq!(img.pixels[k], want, "{object:?} {lambda:?} pixel {k}");
            }
        }
        // The simplified truth is the constant too (up to the f64 sum's rounding).
        assert!(st.simplified.max.iter().all(|&m| m <= 1.0), "{st:?}");
        // With the cos φ test light from below the horizon is lost: never brighter.
        for k in 0..img.pixels.len() {
            if img.mask[k] {
                let got = truth.cos_phi.pixels[k];
                assert!(got.iter().zip(&want).all(|(g, w)| g <= w), "{got:?}");
            }
        }
        assert!(st.cos_phi.is_finite());
    }
}

#[test]
fn sphere_silhouette_covers_the_expected_pixels() {
    let (env, map) = pattern();
    let opt = RenderOptions {
        background: Background::Black,
        ..RenderOptions::default()
    };
    let (img, _, st) = render_object_with(
        env,
        map,
        Object::Sphere,
        LambdaSpec::Uniform(1.0),
        SIZE,
        &opt,
    )
    .unwrap();
    let cam = CameraView::new(
        &glare_pipeline::pipeline::envmap::render::camera(),
        ImageSize {
            width: SIZE.0,
            height: SIZE.1,
        },
    );
    let mut analytic = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            // Distance of the pixel-centre ray from the sphere's centre (the origin).
            let d = cam.ray_dir(x as f64 + 0.5, y as f64 + 0.5);
            let b = -cam.eye.dot(d);
            let dist = (cam.eye.dot(cam.eye) - b * b).max(0.0).sqrt();
            if dist < 1.0 {
                analytic += 1;
            }
            // The 48 × 24 UV sphere is inscribed: its faces are ≥ cos(π/24)·cos(π/48)
            // ≈ 0.989 from the centre, its vertices on the sphere (± the 1/16-pixel
            // vertex snapping ≈ 0.003 radii here).
            if dist < 0.985 {
                assert!(img.covered(x, y), "({x}, {y}) dist {dist} not covered");
            }
            if dist > 1.005 {
                assert!(!img.covered(x, y), "({x}, {y}) dist {dist} covered");
                assert_eq!(img.get(x, y), [0, 0, 0]);
            }
        }
    }
    let got = img.coverage() as f64;
    assert!(
        (got - analytic as f64).abs() <= 0.03 * analytic as f64,
        "coverage {got} vs analytic {analytic}"
    );
    assert_eq!(st.cos_phi.pixels, img.coverage());
    let c = &st.counters["texture_sampler (envmap)"];
    assert_eq!(c.pixels_in as usize, img.coverage());
}

#[test]
fn pattern_lambda_one_error_is_finite_and_reported() {
    let (env, map) = pattern();
    for object in [Object::Sphere, Object::Teapot] {
        let (img, _, st) = render_object(env, map, object, LambdaSpec::Uniform(1.0), SIZE).unwrap();
        assert!(st.cos_phi.is_finite() && st.simplified.is_finite());
        assert!(img.coverage() > 300);
        println!(
            "{object:?} λ=1 s={S} pattern 64×32: |Δ| mean {:?} var {:?} max {:?} signed {:?} \
             (cos φ truth); simplified mean {:?} max {:?}; {} px ({} with n·v < 0), {} triangles",
            st.cos_phi.mean,
            st.cos_phi.var,
            st.cos_phi.max,
            st.cos_phi.mean_signed,
            st.simplified.mean,
            st.simplified.max,
            st.cos_phi.pixels,
            st.back_normal_pixels,
            st.triangles
        );
        // A loose sanity bound (the measured values are a few levels, see the report).
        assert!(mean3(st.simplified.mean) < 16.0, "{st:?}");
    }
}

#[test]
fn error_as_lambda_falls() {
    let (env, map) = pattern();
    let mut means = Vec::new();
    for l in [1.0, 0.75, 0.5, 0.25] {
        let (_, _, st) =
            render_object(env, map, Object::Sphere, LambdaSpec::Uniform(l), SIZE).unwrap();
        println!(
            "sphere λ={l}: cos φ |Δ| mean {:?} var {:?}; simplified |Δ| mean {:?}",
            st.cos_phi.mean, st.cos_phi.var, st.simplified.mean
        );
        means.push(mean3(st.simplified.mean));
    }
    // Reported, and checked only end to end: λ = 0.25 errs more than λ = 1.
    assert!(
        means[3] > means[0],
        "error did not grow from λ = 1 to 0.25: {means:?}"
    );
}

#[test]
fn non_uniform_lambda_renders() {
    let (env, map) = pattern();
    for object in [Object::Sphere, Object::Teapot] {
        let (img, truth, st) =
            render_object(env, map, object, LambdaSpec::NonUniform, SIZE).unwrap();
        assert!(img.coverage() > 300);
        assert_eq!(truth.cos_phi.coverage(), img.coverage());
        assert!(st.cos_phi.is_finite() && st.simplified.is_finite());
        println!(
            "{object:?} non-uniform: cos φ |Δ| mean {:?} var {:?} max {:?}",
            st.cos_phi.mean, st.cos_phi.var, st.cos_phi.max
        );
    }
}

#[test]
fn rim_pixels_and_stiff_cases_are_defined() {
    let (env, map) = pattern();
    // λ = 0 everywhere: t = 0, the centre voxel, Λ = 0 in the truth.
    let (img0, _, st0) =
        render_object(env, map, Object::Sphere, LambdaSpec::Uniform(0.0), SIZE).unwrap();
    assert!(st0.cos_phi.is_finite() && img0.coverage() > 300);
    // The rim (object pixels next to the background): grazing n ⟂ v.
    let (img, truth, st) =
        render_object(env, map, Object::Sphere, LambdaSpec::Uniform(1.0), SIZE).unwrap();
    let (w, h) = (img.width, img.height);
    let mut rim = 0;
    let mut rim_err = [0.0; 3];
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            if !img.covered(x, y) {
                continue;
            }
            let edge = [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                .iter()
                .any(|&(a, b)| !img.covered(a, b));
            if edge {
                rim += 1;
                let (a, b) = (img.get(x, y), truth.cos_phi.pixels[(y * w + x) as usize]);
                for (e, (p, q)) in rim_err.iter_mut().zip(a.iter().zip(&b)) {
                    *e += (*p as f64 - *q as f64).abs();
                }
            }
        }
    }
    assert!(rim > 50, "{rim} rim pixels");
    let rim_mean = rim_err.map(|e| e / rim as f64);
    println!(
        "rim: {rim} px, cos φ |Δ| mean {rim_mean:?} vs whole object {:?}",
        st.cos_phi.mean
    );
    assert!(rim_mean.iter().all(|v| v.is_finite()));
    // A sun at 10⁵ × the rest.
    let mut texels = vec![[0.1; 3]; 64 * 32];
    texels[10 * 64 + 20] = [1e4; 3];
    let sun = EnvMap::new(64, 32, texels).unwrap();
    let sun_map = quick_map(&sun, 8).unwrap();
    let (_, _, st) = render_object(
        &sun,
        &sun_map,
        Object::Teapot,
        LambdaSpec::NonUniform,
        (32, 32),
    )
    .unwrap();
    assert!(st.cos_phi.is_finite());
}

#[test]
fn invalid_inputs_name_their_field() {
    let (env, map) = pattern();
    for (l, field) in [
        (f64::NAN, "envmap_render.lambda"),
        (1.5, "envmap_render.lambda"),
        (-0.1, "envmap_render.lambda"),
    ] {
        let e = render_object(env, map, Object::Sphere, LambdaSpec::Uniform(l), SIZE).unwrap_err();
        assert_eq!(e.field(), field);
    }
    for size in [(0, 8), (8, 0), (5000, 8)] {
        let e =
            render_object(env, map, Object::Sphere, LambdaSpec::Uniform(1.0), size).unwrap_err();
        assert_eq!(e.field(), "envmap_render.size");
    }
    let opt = RenderOptions {
        exposure: Some(f64::INFINITY),
        ..RenderOptions::default()
    };
    let e = render_object_with(
        env,
        map,
        Object::Sphere,
        LambdaSpec::Uniform(1.0),
        SIZE,
        &opt,
    )
    .unwrap_err();
    assert_eq!(e.field(), "envmap.exposure");
}

#[test]
fn table5_rows_are_produced() {
    let (env, map) = pattern();
    let rows = table5_rows(env, "pattern", map, false, &[Object::Sphere], (32, 32)).unwrap();
    assert_eq!(rows.len(), 5);
    println!("{}", Table5Row::CSV_HEADER);
    for r in &rows {
        let line = r.to_csv();
        println!("{line}");
        assert_eq!(line.split(',').count(), 10);
        assert!(line.starts_with("sphere,pattern,"));
    }
    assert_eq!(rows[4].lambda, "nonuniform");
}

/// Writes sphere and teapot at λ = 1, 0.5, 0.25 and non-uniform (rendered | cos φ truth
/// | |Δ| × 8) to the temp directory. Slow-ish (s = 32 map): run with --ignored.
#[test]
#[ignore]
fn write_look_pngs() {
    let env = EnvMap::pattern(64, 32);
    let map = quick_map(&env, 32).unwrap();
    let dir = std::env::temp_dir();
    for object in [Object::Sphere, Object::Teapot] {
        for lambda in [
            LambdaSpec::Uniform(1.0),
            LambdaSpec::Uniform(0.5),
            LambdaSpec::Uniform(0.25),
            LambdaSpec::NonUniform,
        ] {
            let (img, truth, st) = render_object(&env, &map, object, lambda, (160, 160)).unwrap();
            let sheet = Image::hstack(&[&img, &truth.cos_phi, &img.diff(&truth.cos_phi, 8.0)]);
            let path = dir.join(format!("envmap_{}_{}.png", object.name(), lambda.label()));
            sheet.write_png(&path).unwrap();
            println!(
                "{}: cos φ |Δ| mean {:?} max {:?}; simplified mean {:?}",
                path.display(),
                st.cos_phi.mean,
                st.cos_phi.max,
                st.simplified.mean
            );
        }
    }
}

/// The default `reflection_vector` unit against the host-f64 reflection it replaced.
/// Bound, per channel and pixel: the unit's coordinate is within B of the exact
/// (t + 1)/2 · s (its derived bound; 0.0556 texel at s = 128 in its datasheet, and the
/// bound only grows with s, so it covers s = 16), the host word within ½ LSB = 2⁻⁹
/// texel; the sampler's pre-rounding value is trilinear in the coordinate (exact 8-bit
/// weights at the defaults), so it moves by ≤ D per texel per axis, D the largest step
/// between neighbouring voxels; the final roundings differ by ≤ 1:
/// |Δ| ≤ 3·D·(B + 2⁻⁹) + 1.
#[test]
fn reflection_unit_matches_the_host_f64_path() {
    let (env, map) = pattern();
    let d = map.max_neighbour_step();
    let bound = 3.0 * d as f64 * (0.0556 + 1.0 / 512.0) + 1.0;
    assert_eq!(RenderOptions::default().reflection, Reflection::Unit);
    for object in [Object::Sphere, Object::Teapot] {
        for lambda in [
            LambdaSpec::Uniform(1.0),
            LambdaSpec::Uniform(0.3),
            LambdaSpec::NonUniform,
        ] {
            let host = RenderOptions {
                reflection: Reflection::HostF64,
                ..RenderOptions::default()
            };
            let (a, truth, sa) =
                render_object_with(env, map, object, lambda, SIZE, &RenderOptions::default())
                    .unwrap();
            let (b, _, sb) = render_object_with(env, map, object, lambda, SIZE, &host).unwrap();
            assert_eq!(a.mask, b.mask);
            let mut worst = 0.0f64;
            let mut sum = 0.0;
            for k in 0..a.pixels.len() {
                if a.mask[k] {
                    for c in 0..3 {
                        let e = (a.pixels[k][c] as f64 - b.pixels[k][c] as f64).abs();
                        worst = worst.max(e);
                        sum += e;
                    }
                }
            }
            let mean = sum / (3 * a.coverage()) as f64;
            println!(
                "{object:?} {lambda:?}: unit vs f64 mean |Δ| {mean:.3}, max {worst} (bound {bound:.1}); truth error {:.3} vs {:.3}",
                mean3(sa.cos_phi.mean),
                mean3(sb.cos_phi.mean)
            );
            assert!(worst <= bound, "{worst} > {bound}");
            assert!(sa.counters.contains_key("reflection_vector"));
            assert!(!sb.counters.contains_key("reflection_vector"));
            assert_eq!(truth.cos_phi.mask, a.mask);
        }
    }
    // A side that is not a power of two has no unit configuration: an error naming it.
    let odd = quick_map(&EnvMap::pattern(16, 8), 12).unwrap();
    let e = render_object(
        env,
        &odd,
        Object::Sphere,
        LambdaSpec::Uniform(1.0),
        (16, 16),
    )
    .unwrap_err();
    assert_eq!(e.field(), "envmap_render.reflection", "{e}");
}
