//! Loading a scene by name: a built-in (every list: the shafts figures, the glare
//! built-ins, the environment scenes, the showcase) or a TOML file.

use super::builtin::{builtin, BUILTIN_NAMES};
use super::builtin_environment::ENVIRONMENT_BUILTIN_NAMES;
use super::builtin_glare::GLARE_BUILTIN_NAMES;
use super::builtin_showcase::SHOWCASE_NAMES;
use super::format::Scene;
use std::path::Path;

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

/// A built-in scene by name, or a TOML scene file by path.
pub fn load_scene(name_or_path: &str) -> Result<Scene, String> {
    if builtin_names().contains(&name_or_path) {
        return builtin(name_or_path).map_err(|e| e.to_string());
    }
    let p = Path::new(name_or_path);
    if p.exists() {
        return Scene::from_file(p).map_err(|e| e.to_string());
    }
    Err(format!(
        "scene: '{name_or_path}' is neither a built-in scene ({}, test) nor a file",
        builtin_names().join(", ")
    ))
}
