//! `glare-pipeline scene NAME`: any name `render --scene` takes, as the file that
//! renders the same: a built-in scene as compact, commented TOML, a `shading-*` scene
//! as its `[shading]` file form, `test` as its `[test_scene]` form; a scene file
//! printed the same way. And `scene --reference FILE`: the scene format's reference
//! (docs/scenes.md) from the field table.

use crate::pipeline::shading::scene_file::ShadingFile;
use crate::scene::load::{builtin_names, load_scene, SHADING_NAMES, TEST_NAME};
use std::path::Path;

/// The scene the reference's worked example shows.
pub const EXAMPLE: &str = "fig6";

/// The text `scene NAME` prints.
pub fn scene_text(name: &str) -> Result<String, String> {
    if name == TEST_NAME {
        return Ok(crate::scene::test_scene::file_toml());
    }
    if SHADING_NAMES.contains(&name) {
        let f = ShadingFile::builtin(name)?;
        return shading_text(&f, &format!("built-in shading scene `{name}`"));
    }
    if builtin_names().contains(&name) {
        return crate::scene::builtin::builtin_toml(name).map_err(|e| e.to_string());
    }
    // A file: printed in the same form (a shading or test-scene file in its own).
    if crate::scene::test_scene::resolve(name)? {
        return Ok(crate::scene::test_scene::file_toml());
    }
    if let Some(f) = ShadingFile::resolve(name)? {
        return shading_text(&f, &format!("shading scene file {name}"));
    }
    let scene = load_scene(name)?;
    crate::scene::print::scene_toml(
        &scene,
        &format!(
            "# Scene file {name} ({}).\n# Every field is in docs/scenes.md.\n\n",
            scene.name
        ),
    )
    .map_err(|e| e.to_string())
}

/// A shading scene's `[shading]` form, commented.
fn shading_text(f: &ShadingFile, what: &str) -> Result<String, String> {
    let header = format!(
        "# The {what} of glare-pipeline: a sphere through the shading units' path\n\
         # (docs/shading.md, docs/optimize.md). Render it with `glare-pipeline render --scene FILE`.\n\
         # scene: the built-in shading scene; image: the sphere view's side, pixels."
    );
    let body = f.to_toml(&header)?;
    Ok(body.replacen(
        "\n[shading.hw]",
        "\n# The widths of the scene's path (`sweep`'s names), bits or log2 sizes; each at its GeForce default here.\n[shading.hw]",
        1,
    ))
}

/// `scene NAME` or `scene --reference FILE`.
pub fn scene_cli(name: Option<&str>, reference: Option<&Path>) -> Result<(), String> {
    if let Some(path) = reference {
        let text = reference_text()?;
        crate::report::atomic::write_bytes(path, text.as_bytes())
            .map_err(|e| format!("reference: {e}"))?;
        println!(
            "wrote {} ({} sections and fields)",
            path.display(),
            crate::scene::fields::FIELDS.len()
        );
        return Ok(());
    }
    let name = name.ok_or("scene: give a scene name (or --reference FILE)")?;
    print!("{}", scene_text(name)?);
    Ok(())
}

/// docs/scenes.md as the generator writes it.
pub fn reference_text() -> Result<String, String> {
    let example = crate::scene::builtin::builtin_toml(EXAMPLE).map_err(|e| e.to_string())?;
    Ok(crate::scene::fields_reference::reference_markdown(
        EXAMPLE, &example,
    ))
}
