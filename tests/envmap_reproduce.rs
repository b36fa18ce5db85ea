//! Smoke tests of `reproduce envmap-table5` and `envmap-images`
//! (src/pipeline/envmap/reproduce.rs) at s = 16 and tiny images, and of the renderer's
//! truth reuse (`render_against`) and its parallel truth (thread-count independent).

use std::path::PathBuf;
use std::sync::OnceLock;

use glare_pipeline::pipeline::envmap::render::{
    quick_map, render_against, render_image, render_object_with, LambdaSpec, Object, RenderOptions,
};
use glare_pipeline::pipeline::envmap::reproduce::{images, table5, RenderRun, TABLE5_ENVS};
use glare_pipeline::pipeline::envmap::table5::Table5Row;
use glare_pipeline::pipeline::envmap::voxmap::VoxelMap;
use glare_pipeline::scene::envmap::EnvMap;

const RUN: RenderRun = RenderRun { s: 16, size: 16 };

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("envmap_reproduce_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn small() -> &'static (EnvMap, VoxelMap, VoxelMap) {
    static P: OnceLock<(EnvMap, VoxelMap, VoxelMap)> = OnceLock::new();
    P.get_or_init(|| {
        let env = EnvMap::pattern(64, 32);
        let a = quick_map(&env, 16).unwrap();
        let b = quick_map(&env, 8).unwrap();
        (env, a, b)
    })
}

#[test]
fn table5_smoke() {
    let dir = out_dir("table5");
    let rows = table5(&dir, RUN).unwrap();
    // 2 envs × 2 objects × 5 λ × {exact, accelerated}.
    assert_eq!(rows.len(), 40);
    for env in TABLE5_ENVS {
        assert_eq!(rows.iter().filter(|r| r.env == env).count(), 20);
    }
    for r in &rows {
        assert!(r
            .mean
            .iter()
            .chain(&r.var)
            .all(|v| v.is_finite() && *v >= 0.0));
    }
    let csv = std::fs::read_to_string(dir.join("table5.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(Table5Row::CSV_HEADER));
    assert_eq!(lines.count(), 40);
    for f in [
        "table5_extra.csv",
        "table5_times.csv",
        "fig20.png",
        "fig21.png",
    ] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn images_smoke() {
    let dir = out_dir("images");
    let files = images(&dir, RUN).unwrap();
    assert_eq!(files.len(), 4);
    for f in &files {
        assert!(f.is_file(), "{} missing", f.display());
        let img = image::open(f).unwrap();
        assert!(img.width() > 16 && img.height() > 16);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn truth_reuse_matches_and_checks_the_scene() {
    let (env, a, b) = small();
    let opt = RenderOptions::default();
    let l = LambdaSpec::Uniform(0.5);
    let (img, truth, st) = render_object_with(env, a, Object::Sphere, l, (24, 24), &opt).unwrap();
    // Same map: reusing the truth gives the same image and statistics.
    let (img2, st2) = render_against(env, a, Object::Sphere, l, (24, 24), &opt, &truth).unwrap();
    assert_eq!(img, img2);
    assert_eq!(st.cos_phi, st2.cos_phi);
    assert_eq!(st.simplified, st2.simplified);
    assert_eq!(
        img,
        render_image(env, a, Object::Sphere, l, (24, 24), &opt).unwrap()
    );
    // Another scene: refused, naming the field.
    let e = render_against(env, a, Object::Teapot, l, (24, 24), &opt, &truth).unwrap_err();
    assert_eq!(e.field(), "envmap_render.truth");
    let e = render_against(env, a, Object::Sphere, l, (20, 24), &opt, &truth).unwrap_err();
    assert_eq!(e.field(), "envmap_render.truth");
    // A map of another side: the truth's Λ = g(|t|) was for s = 16, refused.
    let e = render_against(env, b, Object::Sphere, l, (24, 24), &opt, &truth).unwrap_err();
    assert_eq!(e.field(), "envmap_render.truth");
}

#[test]
fn parallel_truth_is_thread_count_independent() {
    let (env, a, _) = small();
    let opt = RenderOptions::default();
    let run = || {
        render_object_with(
            env,
            a,
            Object::Teapot,
            LambdaSpec::NonUniform,
            (24, 24),
            &opt,
        )
        .unwrap()
    };
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(run);
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(run);
    assert_eq!(one.0, two.0);
    assert_eq!(one.1, two.1);
    assert_eq!(one.2.cos_phi, two.2.cos_phi);
}

/// `reproduce envmap-lambda-sweep` at s = 16, 16 × 16: every (object, bits, λ) row,
/// finite, the CSV and its header.
#[test]
fn lambda_sweep_smoke() {
    use glare_pipeline::pipeline::envmap::studies::{
        lambda_sweep, SweepRow, SWEEP_BITS, SWEEP_LAMBDAS,
    };
    let dir = out_dir("sweep");
    let rows = lambda_sweep(&dir, RUN).unwrap();
    assert_eq!(rows.len(), 2 * SWEEP_BITS.len() * SWEEP_LAMBDAS.len());
    for r in &rows {
        assert!(r.pixels > 0);
        assert!(r
            .cos_phi
            .iter()
            .chain(&r.simplified)
            .all(|v| v.is_finite() && *v >= 0.0));
        assert!(r.rim_term().is_finite());
    }
    let csv = std::fs::read_to_string(dir.join("lambda_sweep.csv")).unwrap();
    assert_eq!(csv.lines().next(), Some(SweepRow::CSV_HEADER));
    assert_eq!(csv.lines().count(), rows.len() + 1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `reproduce envmap-roughness` at s = 16, 16 × 16: per vertex and texture rows for both
/// objects; on the sphere the texture's λ is closer to the intended one; the PNG exists.
#[test]
fn roughness_smoke() {
    use glare_pipeline::pipeline::envmap::roughness_comparison::RoughnessRow;
    use glare_pipeline::pipeline::envmap::studies::roughness;
    let dir = out_dir("roughness");
    let rows = roughness(&dir, RUN).unwrap();
    assert_eq!(rows.len(), 4);
    let (pv, tx) = (&rows[0], &rows[1]);
    assert_eq!(
        (pv.object.as_str(), tx.object.as_str()),
        ("sphere", "sphere")
    );
    assert!(
        tx.lambda_mean < pv.lambda_mean,
        "texture λ error {} vs per vertex {}",
        tx.lambda_mean,
        pv.lambda_mean
    );
    let csv = std::fs::read_to_string(dir.join("roughness.csv")).unwrap();
    assert_eq!(csv.lines().next(), Some(RoughnessRow::CSV_HEADER));
    assert!(dir.join("roughness_sphere.png").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}
