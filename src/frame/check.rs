//! Everything a scene goes through before its first pixel, as one call: parse the TOML
//! text, validate every field, and elaborate the chip. No file is read (light-map
//! images and environment maps are opened only when a frame is rendered) and nothing
//! is rendered, so the call is cheap enough to run millions of times: it is the path
//! the fuzz target (`tests/fuzz`) and the scene-mutation property test drive.

use super::chip::{elaborate, Chip};
use crate::scene::format::Scene;
use rtl_model::ConfigError;

/// Parse, validate and elaborate a scene from TOML text. Every refusal is a
/// [`ConfigError`] naming the field; nothing here may panic, whatever the text.
pub fn check_scene_text(text: &str) -> Result<(Scene, Chip), ConfigError> {
    let scene = Scene::from_toml_str(text)?;
    let chip = elaborate(&scene);
    Ok((scene, chip))
}
