//! `[shading_hw]`: the widths of the shading units a frame's object pass runs (the
//! normalisation cube map, the specular lookup, the factor textures). Without the
//! section every width is the GeForce default the shading path has always used, so
//! scenes written before it render as before; `sweep` and `attribute` on a frame
//! scene set these fields.
//!
//! The names are those of `sweep --scene shading-<model>`: `cube_face` (the cube
//! map's face side F, a power of two in 2 ..= 512: 6F rows fit the sampler's 4096),
//! `lookup_log2` (log2 of the specular lookup's entries, 1 ..= 12), `factor_size`
//! (the factor textures' side, 1 ..= 4096), `factor_bits` (their texel bits,
//! 1 ..= 16).

use rtl_model::error::ConfigError;
use serde::{Deserialize, Serialize};

/// The sweepable fields, in the order help texts list them.
pub const SHADING_HW_FIELDS: &[&str] = &["cube_face", "lookup_log2", "factor_size", "factor_bits"];

/// `[shading_hw]` (module notes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ShadingHw {
    pub cube_face: u32,
    pub lookup_log2: u32,
    pub factor_size: u32,
    pub factor_bits: u32,
}

impl Default for ShadingHw {
    /// The shading path's GeForce defaults: a 64² × 6 cube, a 256-entry lookup, 64²
    /// factor textures of 8 bits.
    fn default() -> Self {
        ShadingHw {
            cube_face: 64,
            lookup_log2: 8,
            factor_size: 64,
            factor_bits: 8,
        }
    }
}

impl ShadingHw {
    /// Set `field` to `v`; an unknown field is an error naming `param`.
    pub fn set(&mut self, field: &str, v: u32) -> Result<(), String> {
        let f = match field {
            "cube_face" => &mut self.cube_face,
            "lookup_log2" => &mut self.lookup_log2,
            "factor_size" => &mut self.factor_size,
            "factor_bits" => &mut self.factor_bits,
            _ => {
                return Err(format!(
                    "param: unknown shading width '{field}' (known: {})",
                    SHADING_HW_FIELDS.join(", ")
                ))
            }
        };
        *f = v;
        Ok(())
    }

    /// Each field within its unit's range (the scene field table's; errors name
    /// `shading_hw.FIELD`).
    pub fn validate(&self) -> Result<(), ConfigError> {
        use super::fields as F;
        F::SHADING_HW_CUBE_FACE.int("shading_hw.cube_face", self.cube_face.into())?;
        F::SHADING_HW_LOOKUP_LOG2.int("shading_hw.lookup_log2", self.lookup_log2.into())?;
        F::SHADING_HW_FACTOR_SIZE.int("shading_hw.factor_size", self.factor_size.into())?;
        F::SHADING_HW_FACTOR_BITS.int("shading_hw.factor_bits", self.factor_bits.into())
    }
}
