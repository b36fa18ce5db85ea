//! A placeholder for the clocked chip's presets (`ChipConfig::preset`), so the frame's
//! `--chip` resolves against the contract before the presets land in `presets.rs`.
//! Delete this file when they do (the real `ChipConfig::preset` replaces it).

use super::config::ChipConfig;
use rtl_model::ConfigError;

impl ChipConfig {
    /// The clocked chip preset `name` ("geforce256", "geforce2-gts", "geforce3",
    /// "glare-asic"): not built yet, an error for every name.
    pub fn preset(name: &str) -> Result<ChipConfig, ConfigError> {
        Err(ConfigError::invalid(
            "chip",
            &format!("the clocked chip's preset {name:?} is being built; use --timing roofline"),
        ))
    }
}
