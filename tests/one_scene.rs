//! One scene type for every command: `scene::load::load_scene` turns every `--scene`
//! string (the built-ins, `test`, every `shading-*`, scene files, the `[shading]`
//! alias, `[test_scene]` files) into a `Scene`, and `render`, `sweep`, `attribute`
//! and `optimize` pick their path from what the scene holds (`Scene::kind`), never
//! from its name. Checked here through the path functions (cheap: nothing renders).

use glare_pipeline::frame::attribute::{attribute_path, AttributePath};
use glare_pipeline::frame::cli::{render_path, RenderPath};
use glare_pipeline::frame::sweep::{sweep_path, SweepPath};
use glare_pipeline::optimize::command::{optimize_path, OptimizePath};
use glare_pipeline::pipeline::shading::scene_file::ShadingFile;
use glare_pipeline::scene::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use glare_pipeline::scene::format::{Scene, SceneKind};
use glare_pipeline::scene::load::{
    builtin_names, every_scene_name, load_frame_scene, load_scene, SHADING_NAMES, TEST_NAME,
};
use std::path::PathBuf;

/// A scratch file of this test process holding `text`.
fn file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("one_scene_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn load_file(name: &str, text: &str) -> Result<Scene, String> {
    load_scene(&file(name, text).display().to_string())
}

#[test]
fn every_builtin_name_resolves_to_a_scene_of_its_kind() {
    let names = every_scene_name();
    assert!(names.contains(&TEST_NAME));
    for s in SHADING_NAMES {
        assert!(names.contains(s), "{s}");
    }
    for name in names {
        let scene = load_scene(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        match scene.kind() {
            SceneKind::Test => assert_eq!(name, TEST_NAME),
            SceneKind::ShadingSphere(s) => {
                assert!(SHADING_NAMES.contains(&name), "{name}");
                assert_eq!(s.scene, name);
                // The section builds the same point as the built-in shading scene.
                assert_eq!(
                    ShadingFile::from_scene(&scene).unwrap(),
                    ShadingFile::builtin(name).unwrap(),
                    "{name}"
                );
            }
            SceneKind::Frame => {
                assert!(builtin_names().contains(&name), "{name}");
                assert!(
                    !scene.camera.is_unset(),
                    "{name}: a frame scene has a camera"
                );
            }
        }
    }
}

#[test]
fn every_command_takes_its_path_from_the_scene_not_the_name() {
    for name in every_scene_name() {
        let scene = load_scene(name).unwrap();
        let render = render_path(&scene);
        let sweep_param = if SHADING_NAMES.contains(&name) {
            "cube_face"
        } else {
            "planes"
        };
        let sweep = sweep_path(&scene, sweep_param, false).unwrap();
        let attribute = attribute_path(&scene).unwrap();
        let optimize = optimize_path(&scene, None);
        if name == TEST_NAME {
            assert_eq!(render, RenderPath::TestScene);
            assert_eq!(sweep, SweepPath::TestScene);
            assert_eq!(attribute, AttributePath::TestScene);
            assert_eq!(optimize, OptimizePath::Refused);
        } else if SHADING_NAMES.contains(&name) {
            assert_eq!(render, RenderPath::ShadingSphere, "{name}");
            assert_eq!(sweep, SweepPath::Shading, "{name}");
            assert_eq!(
                sweep_path(&scene, sweep_param, true).unwrap(),
                SweepPath::Shading,
                "{name}: --attribute on a shading sphere is the attributed sweep"
            );
            assert_eq!(attribute, AttributePath::Shading, "{name}");
            assert_eq!(optimize, OptimizePath::ShadingWidths, "{name}");
        } else {
            let env = ENVIRONMENT_BUILTIN_NAMES.contains(&name);
            assert_eq!(
                render,
                if env {
                    RenderPath::Environment
                } else {
                    RenderPath::Frame
                },
                "{name}"
            );
            assert_eq!(sweep == SweepPath::Environment, env, "{name}: {sweep:?}");
            assert!(
                !matches!(sweep, SweepPath::TestScene | SweepPath::Shading),
                "{name}: {sweep:?}"
            );
            assert!(
                !matches!(attribute, AttributePath::TestScene | AttributePath::Shading),
                "{name}: {attribute:?}"
            );
            assert_eq!(optimize, OptimizePath::SceneWidths, "{name}");
            assert_eq!(
                optimize_path(&scene, Some("cache_kb")),
                OptimizePath::Chip,
                "{name}"
            );
            assert_eq!(
                sweep_path(&scene, "cache_kb", false).unwrap(),
                SweepPath::Chip,
                "{name}"
            );
            assert_eq!(
                sweep_path(&scene, "planes", true).unwrap(),
                SweepPath::AttributeRefused,
                "{name}"
            );
        }
    }
    // The kind follows the content: the same shading sphere from a file whose name
    // says nothing takes the same paths.
    let s = load_file("plain.toml", "[shading_sphere]\nscene = \"shading-ward\"\n").unwrap();
    assert_eq!(render_path(&s), RenderPath::ShadingSphere);
    assert_eq!(
        sweep_path(&s, "cube_face", false).unwrap(),
        SweepPath::Shading
    );
    let t = load_file("plain_test.toml", "[test_scene]\n").unwrap();
    assert_eq!(render_path(&t), RenderPath::TestScene);
}

#[test]
fn the_shading_alias_and_the_section_load_to_equal_scenes() {
    let cases = [
        "scene = \"shading-blinn_phong\"\n",
        "scene = \"shading-phong\"\nimage = 64\nchip = \"nv2a\"\n\n[{T}.hw]\ncube_face = 32\nlookup_log2 = 7\n",
        "scene = \"shading-vertex\"\nchip = \"nv2a\"\n\n[{T}.hw]\nvertex_mantissa = 12\n",
        "scene = \"shading-specular\"\n\n[{T}.hw]\ncombiner_bits = 10\n",
    ];
    for (i, body) in cases.iter().enumerate() {
        let alias = format!("[shading]\n{}", body.replace("{T}", "shading"));
        let section = format!(
            "[shading_sphere]\n{}",
            body.replace("{T}", "shading_sphere")
        );
        let a = load_file(&format!("alias{i}.toml"), &alias).unwrap();
        let b = load_file(&format!("section{i}.toml"), &section).unwrap();
        assert_eq!(a, b, "{body}");
        assert!(matches!(a.kind(), SceneKind::ShadingSphere(_)));
        let fa = ShadingFile::from_scene(&a).unwrap();
        assert_eq!(fa, ShadingFile::from_scene(&b).unwrap(), "{body}");
        // The alias text as `ShadingFile::parse` reads it builds the same point.
        assert_eq!(fa, ShadingFile::parse(&alias).unwrap(), "{body}");
        // The section written back from the point loads to the same point.
        let mut back = Scene::blank();
        back.shading_sphere = Some(fa.to_section());
        let text = toml::to_string(&back).unwrap();
        let again = Scene::from_toml_str(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(ShadingFile::from_scene(&again).unwrap(), fa, "{text}");
    }
    // A built-in shading scene's name and its one-line section are the same scene.
    assert_eq!(
        load_scene("shading-ward").unwrap(),
        load_file("ward.toml", "[shading_sphere]\nscene = \"shading-ward\"\n").unwrap()
    );
    // `test` and its file form are the same scene.
    assert_eq!(
        load_scene("test").unwrap(),
        load_file("test.toml", "[test_scene]\n").unwrap()
    );
    assert_eq!(load_scene("test").unwrap(), Scene::test_scene());
}

#[test]
fn scene_name_prints_a_shading_sphere_that_loads_back_the_same() {
    use glare_pipeline::frame::scene_text::scene_text;
    for name in SHADING_NAMES {
        let text = scene_text(name).unwrap();
        let back = load_file(&format!("{name}.toml"), &text).unwrap();
        assert_eq!(
            ShadingFile::from_scene(&back).unwrap(),
            ShadingFile::builtin(name).unwrap(),
            "{name}"
        );
        // A section file prints in the same form.
        let p = file(
            &format!("{name}_section.toml"),
            &format!("[shading_sphere]\nscene = \"{name}\"\n"),
        );
        let printed = scene_text(&p.display().to_string()).unwrap();
        assert_eq!(
            ShadingFile::parse(&printed).unwrap(),
            ShadingFile::builtin(name).unwrap(),
            "{name}"
        );
    }
}

/// The error of `text` as a scene file: the field it names must lead the message.
fn refused(text: &str, field: &str) -> String {
    let e = match load_file("refused.toml", text) {
        Ok(s) => match ShadingFile::from_scene(&s) {
            Ok(_) => panic!("accepted: {text}"),
            Err(e) => e,
        },
        Err(e) => e,
    };
    assert!(
        e.contains(&format!("{field}:")),
        "{text}\nwants {field}, got: {e}"
    );
    e
}

#[test]
fn a_mixed_or_bad_section_is_refused_naming_the_field() {
    let sphere = "[shading_sphere]\nscene = \"shading-phong\"\n";
    let object =
        "[[objects]]\nshape = { type = \"sphere\", center = [0.0, 0.0, 0.0], radius = 1.0 }\n";
    refused(&format!("{sphere}{object}"), "objects");
    refused(
        &format!("{sphere}[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n"),
        "camera",
    );
    refused(
        &format!("{sphere}[[lights]]\nposition = [0.0, 5.0, 0.0]\n"),
        "lights",
    );
    refused(
        &format!("{sphere}[image]\nwidth = 64\nheight = 64\n"),
        "image",
    );
    refused(&format!("{sphere}[test_scene]\n"), "shading_sphere");
    // The test scene's section with anything else, and with a field.
    refused(&format!("[test_scene]\n{object}"), "objects");
    refused("[test_scene]\nsize = 3\n", "test_scene.size");
    // The section's own fields, each by its path.
    refused(
        "[shading_sphere]\nscene = \"shading-chrome\"\n",
        "shading_sphere.scene",
    );
    refused(
        "[shading_sphere]\nscene = \"shading-phong\"\nimage = 1\n",
        "shading_sphere.image",
    );
    refused(
        "[shading_sphere]\nscene = \"shading-vertex\"\nimage = 64\n",
        "shading_sphere.image",
    );
    refused(
        "[shading_sphere]\nscene = \"shading-phong\"\nchip = \"voodoo\"\n",
        "shading_sphere.chip",
    );
    refused(
        "[shading_sphere]\nscene = \"shading-phong\"\n[shading_sphere.hw]\ncube_face = 3\n",
        "shading_sphere.hw.cube_face",
    );
    refused(
        "[shading_sphere]\nscene = \"shading-lambert\"\n[shading_sphere.hw]\nlookup_log2 = 7\n",
        "shading_sphere.hw.lookup_log2",
    );
    // The alias keeps naming `shading.*`.
    refused(
        "[shading]\nscene = \"shading-phong\"\n[shading.hw]\ncube_face = 3\n",
        "shading.hw.cube_face",
    );
    refused(
        "[shading]\nscene = \"shading-phong\"\nimage = 1\n",
        "shading.image",
    );
    // A scene of lights and objects still needs its camera.
    let e = refused("name = \"no camera\"\n", "camera");
    assert!(e.contains("missing field"), "{e}");
}

#[test]
fn tools_of_lights_and_objects_refuse_the_other_kinds() {
    let e = load_frame_scene("test").unwrap_err();
    assert!(e.contains("foundation test scene"), "{e}");
    let e = load_frame_scene("shading-phong").unwrap_err();
    assert!(e.contains("shading scene"), "{e}");
    assert!(load_frame_scene("fig6").is_ok());
}
