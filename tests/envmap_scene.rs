//! Environment-map scenes (`[environment]`, src/scene/environment.rs) and their
//! renderer (src/pipeline/envmap/scene_render.rs): a scene renders exactly as the
//! reproductions and the golden test render the thesis objects; an `hdr` file scene
//! equals the built-in of the same map; relative `hdr` paths resolve against the scene
//! file; bad input names its field before any work; `render_geometry` is
//! `render_frame` for the thesis object. Reduced sizes throughout (s = 16, 32 × 32).

use std::path::{Path, PathBuf};
use std::process::Command;

use glare_pipeline::pipeline::envmap::objects::{camera, object_geometry};
use glare_pipeline::pipeline::envmap::prefilter::{build_accelerated, env_to_levels};
use glare_pipeline::pipeline::envmap::render::{
    render_frame, render_geometry, render_object_with, LambdaSpec, Lookup, Object, RenderOptions,
};
use glare_pipeline::pipeline::envmap::reproduce::TABLE5_TH;
use glare_pipeline::pipeline::envmap::scene_render::{render_scene, SceneFrame};
use glare_pipeline::pipeline::envmap::voxmap::VoxelMap;
use glare_pipeline::reference::envmap_prefilter::PrefilterParams;
use glare_pipeline::scene::builtin::{builtin, builtin_toml};
use glare_pipeline::scene::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use glare_pipeline::scene::camera::CameraView;
use glare_pipeline::scene::environment::{
    EnvBackground, EnvLambda, EnvLookup, EnvObject, Prefilter,
};
use glare_pipeline::scene::envmap::{EnvMap, BUILTIN_NAMES as MAP_NAMES, MAX_HDR_BYTES};
use glare_pipeline::scene::format::{ImageSize, Scene};

const S: u32 = 16;
const SIDE: u32 = 32;

fn venice_hdr() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src/scene/data/envmaps/venice_sunset_512.hdr")
}

fn temp_dir(what: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("envmap-scene-{what}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A built-in environment scene at the test size.
fn small_builtin(name: &str) -> Scene {
    let mut s = builtin(name).unwrap();
    s.image = ImageSize {
        width: SIDE,
        height: SIDE,
    };
    s.environment.as_mut().unwrap().side = S;
    s
}

/// The venice sunset teapot as a scene file would state it, with `hdr` given.
fn venice_teapot_toml(hdr: &str) -> String {
    format!(
        r#"
name = "venice teapot from a file"
[image]
width = {SIDE}
height = {SIDE}
[camera]
eye = [0.0, 1.0, 3.9]
look_at = [0.0, 0.0, 0.0]
fovy_deg = 36.0
near = 1.0
far = 10.0
[environment]
hdr = "{hdr}"
side = {S}
object = "teapot"
lambda = "nonuniform"
"#
    )
}

/// The map the golden test and `reproduce envmap-images` make.
fn golden_map(map_name: &str) -> (EnvMap, VoxelMap) {
    let env = EnvMap::builtin(map_name).unwrap();
    let levels = env_to_levels(&env, env.auto_exposure()).unwrap();
    let (map, _) = build_accelerated(&levels, S, &PrefilterParams::thesis(), TABLE5_TH).unwrap();
    (env, map)
}

fn assert_same_render(a: &SceneFrame, b: &SceneFrame, what: &str) {
    assert_eq!(a.image, b.image, "{what}: image");
    assert_eq!(a.counters, b.counters, "{what}: counters");
    assert_eq!(a.frame, b.frame, "{what}: frame");
}

#[test]
fn builtin_names_cover_every_map_and_object_and_round_trip_as_toml() {
    assert_eq!(ENVIRONMENT_BUILTIN_NAMES.len(), MAP_NAMES.len() * 2);
    for map in MAP_NAMES {
        for object in ["sphere", "teapot"] {
            let name = format!("env-{map}-{object}");
            assert!(ENVIRONMENT_BUILTIN_NAMES.contains(&name.as_str()), "{name}");
            let s = builtin(&name).unwrap();
            let e = s.environment.as_ref().unwrap();
            assert_eq!(e.map.as_deref(), Some(map));
            assert_eq!(e.object.map(EnvObject::name), Some(object));
            assert_eq!(s.camera, camera());
            let text = builtin_toml(&name).unwrap();
            assert!(text.contains("[environment]"), "{text}");
            assert_eq!(Scene::from_toml_str(&text).unwrap(), s, "{name}");
        }
    }
    // The existing names still work, and unknown ones list the new ones.
    assert!(builtin("fig6").unwrap().environment.is_none());
    assert!(builtin("glare-point").unwrap().environment.is_none());
    let e = builtin("env-pattern-cube").unwrap_err();
    assert_eq!(e.field(), "scene");
    assert!(
        e.to_string().contains("env-st_fagans_interior-teapot"),
        "{e}"
    );
}

#[test]
fn a_minimal_section_takes_the_thesis_defaults() {
    let text = "[camera]\neye = [0.0, 1.0, 3.9]\nlook_at = [0.0, 0.0, 0.0]\n[environment]\nmap = \"pattern\"\n";
    let e = Scene::from_toml_str(text).unwrap().environment.unwrap();
    assert_eq!(e.side, 128);
    // The default picks the faster build at the side (issue 17): the thesis'
    // accelerated one at 128 and below, the exact one above.
    assert_eq!(e.prefilter, Prefilter::Auto);
    for side in [2, 64, 128] {
        assert_eq!(
            e.prefilter.resolve(side),
            Prefilter::Accelerated {
                threshold: TABLE5_TH
            }
        );
    }
    assert_eq!(e.prefilter.resolve(256), Prefilter::Exact);
    let exact = Prefilter::Exact;
    assert_eq!(exact.resolve(64), Prefilter::Exact);
    let acc = Prefilter::Accelerated { threshold: 0.01 };
    assert_eq!(acc.resolve(256), acc);
    assert_eq!(e.lambda, EnvLambda::Uniform(1.0));
    assert_eq!(e.lookup, EnvLookup::Voxel3d);
    assert_eq!(e.background, EnvBackground::Environment);
    assert_eq!((e.exposure, e.object, e.hdr), (None, None, None));
    // An integer λ is a number; the written section round-trips.
    let one = Scene::from_toml_str(&text.replace("map =", "lambda = 0\nmap ="))
        .unwrap()
        .environment
        .unwrap();
    assert_eq!(one.lambda, EnvLambda::Uniform(0.0));
    let s = Scene::from_toml_str(text).unwrap();
    assert_eq!(
        Scene::from_toml_str(&toml::to_string(&s).unwrap()).unwrap(),
        s
    );
}

#[test]
fn builtin_scenes_render_as_the_golden_path() {
    for (name, map_name, object, lambda) in [
        (
            "env-pattern-sphere",
            "pattern",
            Object::Sphere,
            LambdaSpec::Uniform(0.5),
        ),
        (
            "env-venice_sunset-teapot",
            "venice_sunset",
            Object::Teapot,
            LambdaSpec::NonUniform,
        ),
    ] {
        let got = render_scene(&small_builtin(name), false).unwrap();
        let (env, map) = golden_map(map_name);
        let opt = RenderOptions::default();
        let (img, info) = render_frame(&env, &map, object, lambda, (SIDE, SIDE), &opt).unwrap();
        assert_eq!(got.image, img, "{name}: image");
        assert_eq!(got.frame, info, "{name}: frame");
        let (_, _, stats) =
            render_object_with(&env, &map, object, lambda, (SIDE, SIDE), &opt).unwrap();
        assert_eq!(got.counters, stats.counters, "{name}: counters");
        assert!(
            got.image.coverage() > 120,
            "{name}: {}",
            got.image.coverage()
        );
        assert_eq!(got.map.side, S);
        assert!(got.prediction.seconds > 0.0 && got.prediction.seconds < 1e-2);
    }
}

#[test]
fn hdr_file_scene_equals_the_builtin_map() {
    let hdr = venice_hdr();
    let text = venice_teapot_toml(&hdr.display().to_string());
    let from_file = Scene::from_toml_str(&text).unwrap();
    // The path is serialised as written.
    let back = toml::to_string(&from_file).unwrap();
    assert!(
        back.contains(&format!("hdr = \"{}\"", hdr.display())),
        "{back}"
    );
    let a = render_scene(&from_file, false).unwrap();
    let b = render_scene(&small_builtin("env-venice_sunset-teapot"), false).unwrap();
    assert_same_render(&a, &b, "hdr vs built-in");
    assert_eq!(a.map.exposure, b.map.exposure);
    assert_eq!(a.map.source, hdr.display().to_string());
    assert_eq!(b.map.source, "venice_sunset");
}

#[test]
fn relative_hdr_resolves_against_the_scene_file() {
    let dir = temp_dir("relative");
    std::fs::create_dir_all(dir.join("maps")).unwrap();
    std::fs::copy(venice_hdr(), dir.join("maps/sunset.hdr")).unwrap();
    let scene_path = dir.join("scene.toml");
    std::fs::write(&scene_path, venice_teapot_toml("maps/sunset.hdr")).unwrap();

    let s = Scene::from_file(&scene_path).unwrap();
    let hdr = s.environment.as_ref().unwrap().hdr.as_ref().unwrap();
    assert_eq!(hdr.written(), "maps/sunset.hdr");
    assert_eq!(hdr.file(), dir.join("maps/sunset.hdr"));
    let back = toml::to_string(&s).unwrap();
    assert!(back.contains("hdr = \"maps/sunset.hdr\""), "{back}");

    // Parsed from text, the same path is relative to the working directory (the
    // crate root here), where it does not exist.
    let e = Scene::from_toml_str(&venice_teapot_toml("maps/sunset.hdr")).unwrap_err();
    assert_eq!(e.field(), "environment.hdr", "{e}");

    let a = render_scene(&s, false).unwrap();
    let b = render_scene(&small_builtin("env-venice_sunset-teapot"), false).unwrap();
    assert_same_render(&a, &b, "relative hdr vs built-in");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_environment_input_names_its_field() {
    let dir = temp_dir("bad");
    let base = venice_teapot_toml(&venice_hdr().display().to_string());
    let with = |from: &str, to: &str| {
        assert!(base.contains(from), "{from}");
        base.replace(from, to)
    };
    let missing = dir.join("nonesuch.hdr").display().to_string();
    let not_hdr = dir.join("not.hdr");
    std::fs::write(&not_hdr, "#?RADIANCE\nnot really\n").unwrap();
    let odd = dir.join("odd.hdr");
    EnvMap::constant(12, 6, [0.5; 3])
        .unwrap()
        .write_hdr(&odd)
        .unwrap();
    let huge = dir.join("huge.hdr");
    // Sparse: no disk used; refused by its size before a byte is read.
    std::fs::File::create(&huge)
        .unwrap()
        .set_len(MAX_HDR_BYTES + 1)
        .unwrap();
    let hdr_line = format!("hdr = \"{}\"", venice_hdr().display());
    let cases: Vec<(String, &str, &str)> = vec![
        (
            with(&hdr_line, &format!("hdr = \"{missing}\"")),
            "environment.hdr",
            "cannot open",
        ),
        (
            with(&hdr_line, &format!("{hdr_line}\nmap = \"pattern\"")),
            "environment.hdr",
            "not both",
        ),
        (with(&hdr_line, ""), "environment.map", "hdr"),
        (
            with(&hdr_line, "map = \"mars\""),
            "environment.map",
            "unknown built-in map",
        ),
        (with(&hdr_line, "hdr = \" \""), "environment.hdr", "empty"),
        (
            with(&hdr_line, &format!("hdr = \"{}\"", not_hdr.display())),
            "environment.hdr",
            "Radiance",
        ),
        (
            with(&hdr_line, &format!("hdr = \"{}\"", dir.display())),
            "environment.hdr",
            "not a regular file",
        ),
        (
            with(&hdr_line, &format!("hdr = \"{}\"", huge.display())),
            "environment.hdr",
            "bytes",
        ),
        (
            with(&hdr_line, &format!("hdr = \"{}\"", odd.display())),
            "environment.hdr",
            "divisible by 8",
        ),
        (
            with("side = 16", "side = 100"),
            "environment.side",
            "power of two",
        ),
        (
            with("side = 16", "side = 1024"),
            "environment.side",
            "out of range",
        ),
        (
            with("side = 16", "side = 1"),
            "environment.side",
            "out of range",
        ),
        (
            with("lambda = \"nonuniform\"", "lambda = 2"),
            "environment.lambda",
            "2",
        ),
        (
            with("lambda = \"nonuniform\"", "lambda = -0.5"),
            "environment.lambda",
            "-0.5",
        ),
        (
            with("lambda = \"nonuniform\"", "lambda = \"rough\""),
            "environment.lambda",
            "nonuniform",
        ),
        (
            with("side = 16", "side = 16\nexposure = 0.0"),
            "environment.exposure",
            "exposure",
        ),
        (
            with(
                "side = 16",
                "side = 16\nprefilter = { type = \"accelerated\", threshold = 1.0 }",
            ),
            "environment.prefilter.threshold",
            "threshold",
        ),
        (
            with("object = \"teapot\"", "object = \"cube\""),
            "environment.object",
            "cube",
        ),
        (
            with("side = 16", "side = 16\nsides = 16"),
            "environment.sides",
            "unknown field",
        ),
    ];
    for (text, want_field, want_text) in &cases {
        let e = Scene::from_toml_str(text).unwrap_err();
        assert_eq!(e.field(), *want_field, "{e}\n{text}");
        assert!(e.to_string().contains(want_text), "{e}");
    }
    // The odd-sized map is fine for the exact prefilter (no pyramid).
    let exact = with(
        &hdr_line,
        &format!(
            "hdr = \"{}\"\nprefilter = {{ type = \"exact\" }}",
            odd.display()
        ),
    );
    let s = Scene::from_toml_str(&exact).unwrap();
    assert_eq!(s.environment.unwrap().prefilter, Prefilter::Exact);
    // An endless device is refused without reading it.
    if Path::new("/dev/zero").exists() {
        let e = Scene::from_toml_str(&with(&hdr_line, "hdr = \"/dev/zero\"")).unwrap_err();
        assert_eq!(e.field(), "environment.hdr");
        assert!(e.to_string().contains("not a regular file"), "{e}");
    }

    // What only the renderer refuses: no object, glare, shafts objects or lights, an
    // image larger than it draws.
    let ok = Scene::from_toml_str(&base).unwrap();
    let mut no_object = ok.clone();
    no_object.environment.as_mut().unwrap().object = None;
    assert!(no_object.validate().is_ok());
    let mut with_objects = ok.clone();
    with_objects.objects = builtin("fig6").unwrap().objects;
    let mut with_lights = ok.clone();
    with_lights.lights = builtin("fig6").unwrap().lights;
    let mut with_glare = ok.clone();
    with_glare.glare = builtin("glare-point").unwrap().glare;
    let mut huge_image = ok.clone();
    huge_image.image.width = 5000;
    for (s, want) in [
        (no_object, "environment.object"),
        (with_objects, "objects"),
        (with_lights, "lights"),
        (with_glare, "glare"),
        (huge_image, "image.width"),
    ] {
        let e = render_scene(&s, false).unwrap_err();
        assert_eq!(e.field(), want, "{e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn render_geometry_is_render_frame_for_the_thesis_objects() {
    let (env, map) = golden_map("pattern");
    let size = (SIDE, 24);
    for (object, lambda, lookup) in [
        (Object::Sphere, LambdaSpec::Uniform(0.5), Lookup::Voxel3D),
        (Object::Sphere, LambdaSpec::Uniform(0.5), Lookup::Auto),
        (Object::Sphere, LambdaSpec::NonUniform, Lookup::Auto),
        (Object::Teapot, LambdaSpec::NonUniform, Lookup::Voxel3D),
    ] {
        let opt = RenderOptions {
            lookup,
            ..RenderOptions::default()
        };
        let cam = CameraView::new(
            &camera(),
            ImageSize {
                width: size.0,
                height: size.1,
            },
        );
        let tris = object_geometry(object, lambda, &cam).unwrap();
        let (img, info, counters) =
            render_geometry(&env, &map, &tris, &camera(), size, &opt).unwrap();
        let (want_img, want_info) = render_frame(&env, &map, object, lambda, size, &opt).unwrap();
        let what = format!("{object:?} {lambda:?} {lookup:?}");
        assert_eq!(img, want_img, "{what}");
        assert_eq!(info, want_info, "{what}");
        // The 2D slice is elaborated exactly for a uniform λ with the auto lookup.
        let uniform = matches!(lambda, LambdaSpec::Uniform(_));
        assert_eq!(
            info.elaboration.slice_2d,
            uniform && lookup == Lookup::Auto,
            "{what}"
        );
        assert!(img.coverage() > 80, "{what}: {}", img.coverage());
        assert_eq!(
            counters["texture_sampler (envmap)"].pixels_in,
            img.coverage() as u64,
            "{what}"
        );
    }
    // Bad λ and a degenerate camera are refused by name.
    let cam = CameraView::new(
        &camera(),
        ImageSize {
            width: SIDE,
            height: SIDE,
        },
    );
    let mut tris = object_geometry(Object::Sphere, LambdaSpec::Uniform(0.5), &cam).unwrap();
    let opt = RenderOptions::default();
    let mut flat = camera();
    flat.look_at = flat.eye;
    let e = render_geometry(&env, &map, &tris, &flat, (SIDE, SIDE), &opt).unwrap_err();
    assert_eq!(e.field(), "camera.look_at");
    tris[3].1[1] = 1.5;
    let e = render_geometry(&env, &map, &tris, &camera(), (SIDE, SIDE), &opt).unwrap_err();
    assert_eq!(e.field(), "envmap_render.lambda");
}

#[test]
fn render_scene_cli_writes_the_same_png_for_the_file_and_the_builtin() {
    let dir = temp_dir("cli");
    let hdr_scene = dir.join("hdr.toml");
    std::fs::write(
        &hdr_scene,
        venice_teapot_toml(&venice_hdr().display().to_string()),
    )
    .unwrap();
    // The built-in as `scene NAME` prints it, shrunk to the test size.
    let builtin_scene = dir.join("builtin.toml");
    let text = builtin_toml("env-venice_sunset-teapot")
        .unwrap()
        .replace("width = 256", &format!("width = {SIDE}"))
        .replace("height = 256", &format!("height = {SIDE}"))
        .replace("side = 128", &format!("side = {S}"));
    std::fs::write(&builtin_scene, text).unwrap();
    let mut pngs = Vec::new();
    let mut counters = Vec::new();
    for (k, scene) in [&hdr_scene, &builtin_scene].into_iter().enumerate() {
        let png = dir.join(format!("{k}.png"));
        let out = Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
            .args(["render", "--json", "--scene"])
            .arg(scene)
            .arg("--out")
            .arg(&png)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert!(v["timing"]["predicted_seconds"].as_f64().unwrap() > 0.0);
        assert_eq!(v["timing"]["gpu"], "GeForce3");
        assert!(v["chip"]["units"].as_array().unwrap().len() >= 2);
        counters.push(v["counters"]["envmap"].clone());
        pngs.push(std::fs::read(&png).unwrap());
    }
    assert_eq!(pngs[0], pngs[1]);
    assert_eq!(counters[0], counters[1]);
    assert!(counters[0]["texture_sampler (envmap)"]["pixels_in"].as_u64() > Some(100));

    // A bad scene file fails before any work, naming the field.
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, venice_teapot_toml("nonesuch.hdr")).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_glare-pipeline"))
        .args(["render", "--scene"])
        .arg(&bad)
        .arg("--out")
        .arg(dir.join("bad.png"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("environment.hdr"), "{err}");
    assert!(!dir.join("bad.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
