//! `glare-pipeline scene NAME`: any name `render --scene` takes, as the file that
//! renders the same: a built-in scene as compact, commented TOML, a `shading-*` scene
//! as its `[shading]` file form (the alias of a `[shading_sphere]` section), `test` as its `[test_scene]` form; a scene file
//! printed the same way. And `scene --reference FILE`: the scene format's reference
//! (docs/scenes.md) from the field table.

use crate::pipeline::shading::scene_file::ShadingFile;
use crate::scene::format::SceneKind;
use crate::scene::load::{builtin_names, load_scene, SHADING_NAMES};
use std::path::Path;

/// The scene the reference's worked example shows.
pub const EXAMPLE: &str = "fig6";

/// The text `scene NAME` prints.
pub fn scene_text(name: &str) -> Result<String, String> {
    if builtin_names().contains(&name) {
        return crate::scene::builtin::builtin_toml(name).map_err(|e| e.to_string());
    }
    let scene = load_scene(name)?;
    match scene.kind() {
        // The test scene in its `[test_scene]` form.
        SceneKind::Test => Ok(crate::scene::test_scene::file_toml()),
        // A shading sphere in its `[shading]` form, every width written out.
        SceneKind::ShadingSphere(s) => {
            let f = ShadingFile::from_section(s)?;
            let what = if SHADING_NAMES.contains(&name) {
                format!("built-in shading scene `{name}`")
            } else {
                format!("shading scene file {name}")
            };
            shading_text(&f, &what)
        }
        SceneKind::Frame => crate::scene::print::scene_toml(
            &scene,
            &format!(
                "# Scene file {name} ({}).\n# Every field is in docs/scenes.md.\n\n",
                scene.name
            ),
        )
        .map_err(|e| e.to_string()),
    }
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
