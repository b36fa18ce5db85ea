//! Everything a scene goes through before its first pixel, as one call: parse the TOML
//! text, validate every field, elaborate the chip and estimate the frame's memory
//! (what `render` checks against its budget before allocating). No file is read (light-map
//! images and environment maps are opened only when a frame is rendered) and nothing
//! is rendered, so the call is cheap enough to run millions of times: it is the path
//! the fuzz target (`tests/fuzz`) and the scene-mutation property test drive.

use super::budget::{estimate, Estimate};
use super::chip::{elaborate, Chip};
use crate::scene::format::Scene;
use rtl_model::ConfigError;

/// A scene that passed: itself, its chip and its memory estimate.
pub struct Checked {
    pub scene: Scene,
    pub chip: Chip,
    pub memory: Estimate,
}

/// Parse, validate, elaborate and size a scene from TOML text. Every refusal is a
/// [`ConfigError`] naming the field; nothing here may panic, whatever the text.
pub fn check_scene_text(text: &str) -> Result<Checked, ConfigError> {
    let scene = Scene::from_toml_str(text)?;
    let chip = elaborate(&scene);
    let memory = estimate(&scene);
    Ok(Checked {
        scene,
        chip,
        memory,
    })
}
