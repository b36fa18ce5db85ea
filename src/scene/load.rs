//! Loading a scene by name, in one place for every command: a built-in (every list:
//! the shafts figures, the glare built-ins, the environment scenes, the showcase, the
//! foundation test scene, the shading spheres) or a TOML file (a scene, or the
//! `[shading]` alias of a shading sphere). A misspelt name gets the nearest names ("did you mean glare-point?"),
//! a path that looks like a file and does not exist gets "file not found".

use super::builtin::{builtin, BUILTIN_NAMES};
use super::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use super::builtin_glare::GLARE_BUILTIN_NAMES;
use super::builtin_showcase::SHOWCASE_NAMES;
use super::format::{Scene, SceneKind};
use std::path::Path;

/// The foundation test scene's name (`render --scene test`).
pub const TEST_NAME: &str = "test";

pub use super::shading_sphere::SHADING_NAMES;

/// Every built-in scene name, in the order help texts list them.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN_NAMES
        .iter()
        .chain(GLARE_BUILTIN_NAMES)
        .chain(ENVIRONMENT_BUILTIN_NAMES)
        .chain(SHOWCASE_NAMES)
        .copied()
        .collect()
}

/// Every name `render --scene` takes: the built-in scenes, `test` and the shading
/// scenes.
pub fn every_scene_name() -> Vec<&'static str> {
    let mut v = builtin_names();
    v.push(TEST_NAME);
    v.extend_from_slice(SHADING_NAMES);
    v
}

/// Whether `name` is meant as a file: it has a path separator or ends in `.toml`.
pub fn looks_like_file(name: &str) -> bool {
    name.contains('/') || name.contains('\\') || name.ends_with(".toml")
}

pub use super::suggest::{did_you_mean, edit_distance, suggest};

/// The error for a scene name that is neither a built-in nor a file.
pub fn unknown_scene(name: &str) -> String {
    if looks_like_file(name) {
        return format!("scene: file not found: {name}");
    }
    let hint = did_you_mean(name, &every_scene_name(), "");
    let hint = if hint.is_empty() {
        String::new()
    } else {
        format!("; {hint}")
    };
    format!(
        "scene: unknown scene '{name}'{hint} (built-in scenes: {}, {TEST_NAME}, {}; or a TOML scene file)",
        builtin_names().join(", "),
        SHADING_NAMES.join(", ")
    )
}

/// A top-level table that makes a file one of the other file forms (not a `Scene`).
pub fn other_form(text: &str) -> Option<&'static str> {
    let t = text.parse::<toml::Table>().ok()?;
    ["shading", "test_scene"]
        .into_iter()
        .find(|k| t.contains_key(*k))
}

/// Any `--scene` string as a [`Scene`], in one place for every command: a built-in
/// name (the lights-and-objects scenes, `test`, every `shading-*`), a TOML scene file,
/// a file with a top-level `[shading]` table (the alias of a `[shading_sphere]`
/// section: its errors name `shading.*`) or a `[test_scene]` file. The scene comes
/// back validated; what it is ([`Scene::kind`]) picks the command's path, not the
/// name. A misspelt name or a missing file gets an error saying so.
pub fn load_scene(name_or_path: &str) -> Result<Scene, String> {
    if builtin_names().contains(&name_or_path) {
        return builtin(name_or_path).map_err(|e| e.to_string());
    }
    if name_or_path == TEST_NAME {
        return Ok(Scene::test_scene());
    }
    let p = Path::new(name_or_path);
    if p.is_file() {
        let text = std::fs::read_to_string(p).ok();
        match text.as_deref().and_then(other_form) {
            Some(super::shading_sphere::ALIAS_TABLE) => {
                let text = text.unwrap_or_default();
                let in_file = |e: String| format!("{e} (in {name_or_path})");
                let section = super::shading_sphere::ShadingSphereSection::from_alias(&text)
                    .map_err(in_file)?;
                let scene = Scene::shading_sphere(section);
                scene.validate().map_err(|e| in_file(e.to_string()))?;
                return Ok(scene);
            }
            Some(_) => {
                let text = text.unwrap_or_default();
                super::test_scene::parse_file(&text)
                    .map_err(|e| format!("{e} (in {name_or_path})"))?;
                return Ok(Scene::test_scene());
            }
            None => {}
        }
    }
    if p.exists() {
        return Scene::from_file(p).map_err(|e| e.to_string());
    }
    if SHADING_NAMES.contains(&name_or_path) {
        return Ok(Scene::shading_sphere(
            super::shading_sphere::ShadingSphereSection::builtin(name_or_path),
        ));
    }
    Err(unknown_scene(name_or_path))
}

/// [`load_scene`] for a tool that takes only a scene of lights and objects (the
/// frame's passes): the test scene and the shading spheres are refused, saying what
/// they are and which commands take them.
pub fn load_frame_scene(name_or_path: &str) -> Result<Scene, String> {
    let scene = load_scene(name_or_path)?;
    match scene.kind() {
        SceneKind::Frame => Ok(scene),
        SceneKind::Test => Err(format!(
            "scene: '{name_or_path}' is the foundation test scene, a fixed scene without \
             lights and objects; `render --scene {name_or_path}` renders it"
        )),
        SceneKind::ShadingSphere(s) => Err(format!(
            "scene: '{name_or_path}' is a shading scene ({}), not a scene of lights and \
             objects; `render`, `sweep`, `optimize` and `attribute` take it",
            s.scene
        )),
    }
}

/// `--image` (if given) set as `scene`'s image size; the scene checks the sides'
/// range when it is validated.
pub fn apply_image(scene: &mut Scene, image: Option<&str>) -> Result<(), String> {
    if let Some(img) = image {
        let (w, h) = crate::report::image_arg::parse_image(img)?;
        scene.image.width = w;
        scene.image.height = h;
    }
    Ok(())
}

/// [`apply_image`], then the scene validated at once: an error names `--image`.
pub fn apply_image_checked(scene: &mut Scene, image: Option<&str>) -> Result<(), String> {
    apply_image(scene, image)?;
    if let Some(img) = image {
        scene
            .validate()
            .map_err(|e| format!("--image {img}: {e}"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_and_suggestions() {
        assert_eq!(edit_distance("fig7", "fig6"), 1);
        assert_eq!(edit_distance("fvo", "fov"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(suggest("glare-pont", &builtin_names()), vec!["glare-point"]);
        assert_eq!(suggest("fig7", &builtin_names()), vec!["fig4", "fig6"]);
        assert_eq!(
            suggest("fvo", &["eye", "look_at", "up", "fovy_deg", "near", "far"]),
            vec!["fovy_deg"]
        );
        assert!(suggest("zzzzzzzz", &builtin_names()).is_empty());
        assert_eq!(
            did_you_mean("glare-pont", &builtin_names(), ""),
            "did you mean glare-point?"
        );
        assert_eq!(
            did_you_mean("fig7", &builtin_names(), ""),
            "did you mean fig4 or fig6?"
        );
    }
}
