//! The shading units' sphere as a section of the scene: `[shading_sphere]` names a
//! built-in shading scene (`shading-<model>`, `shading-specular`, `shading-vertex`),
//! the sphere view's side, the chip preset and the widths of the scene's path. A
//! scene holding it is the sphere and nothing else (no camera, lights, objects, glare
//! or environment: validation refuses the mix, naming the field).
//!
//! ```toml
//! [shading_sphere]
//! scene = "shading-blinn_phong"   # a built-in shading scene
//! image = 64                      # the sphere view's side in pixels (default 256)
//! chip = "nv2a"                   # the chip preset (default "geforce2")
//!
//! [shading_sphere.hw]             # the scene's widths (`sweep`'s names); a width
//! cube_face = 32                  # not given keeps its GeForce default
//! ```
//!
//! A file whose top-level table is `[shading]` with the same keys (what earlier
//! versions wrote as `optimize`'s best.toml) is an alias: it reads as this section,
//! and its errors name `shading.*`. Here are the checks that need no unit: the
//! scene's name, the image side, the chip; the widths are checked against the
//! scene's units where the shading pipeline builds them
//! (`pipeline::shading::scene_file::ShadingFile::from_section`), before any work.

use rtl_model::chip_preset::ChipPreset;
use rtl_model::error::ConfigError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The section's table in a scene file.
pub const TABLE: &str = "shading_sphere";
/// The alias file form's top-level table.
pub const ALIAS_TABLE: &str = "shading";
/// The sphere view's side when the section gives none (the `shading-brdfs` view).
pub const DEFAULT_IMAGE: u32 = 256;
/// The shading scene that lights sphere vertices and has no image.
pub const VERTEX: &str = "shading-vertex";

/// Every built-in shading scene (`shading-<model>`, `shading-specular`,
/// `shading-vertex`): the names `render --scene` takes for the shading units' spheres.
/// The shading pipeline defines them; tests/scene.rs checks this list against it.
pub const SHADING_NAMES: &[&str] = &[
    "shading-lambert",
    "shading-oren_nayar",
    "shading-phong",
    "shading-blinn_phong",
    "shading-cook_torrance_metal",
    "shading-cook_torrance_dielectric",
    "shading-cook_torrance_backlit",
    "shading-ward",
    "shading-kajiya_kay",
    "shading-specular",
    "shading-vertex",
];

/// `[shading_sphere]`: which shading sphere, at which size, chip and widths.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShadingSphereSection {
    /// A built-in shading scene's name ([`SHADING_NAMES`]).
    pub scene: String,
    /// The sphere view's side in pixels, 2 ..= 4096; none = 256 (`shading-vertex`
    /// has no image and takes none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<u32>,
    /// The chip preset whose modes the path's units follow; left out = the GeForce2.
    #[serde(default, skip_serializing_if = "ChipPreset::is_default")]
    pub chip: ChipPreset,
    /// Widths of the scene's path by `sweep`'s names; a width not given keeps its
    /// GeForce default.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub hw: BTreeMap<String, u32>,
    /// The table the section was read from ([`TABLE`], or [`ALIAS_TABLE`] for the
    /// alias file form): error messages name its fields under it. Not part of the
    /// scene: two sections that differ only here are equal.
    #[serde(skip, default = "default_table")]
    pub table: &'static str,
}

fn default_table() -> &'static str {
    TABLE
}

impl PartialEq for ShadingSphereSection {
    fn eq(&self, o: &Self) -> bool {
        self.scene == o.scene && self.image == o.image && self.chip == o.chip && self.hw == o.hw
    }
}

/// The alias file form: a top-level `[shading]` table and nothing else.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AliasForm {
    shading: AliasSection,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AliasSection {
    scene: String,
    #[serde(default)]
    image: Option<u32>,
    /// A chip preset's name; anything else is an error naming `shading.chip`.
    #[serde(default)]
    chip: Option<toml::Value>,
    #[serde(default)]
    hw: BTreeMap<String, u32>,
}

impl ShadingSphereSection {
    /// A built-in shading scene at its defaults.
    pub fn builtin(name: &str) -> ShadingSphereSection {
        ShadingSphereSection {
            scene: name.to_string(),
            image: None,
            chip: ChipPreset::GeForce2,
            hw: BTreeMap::new(),
            table: TABLE,
        }
    }

    /// The sphere view's side: the section's, or [`DEFAULT_IMAGE`]; none for
    /// `shading-vertex`.
    pub fn side(&self) -> Option<u32> {
        (self.scene != VERTEX).then(|| self.image.unwrap_or(DEFAULT_IMAGE))
    }

    /// The path of one of the section's fields as the file spelt it
    /// (`shading_sphere.image`, or `shading.image` in the alias form).
    pub fn field(&self, name: &str) -> String {
        format!("{}.{name}", self.table)
    }

    /// The alias file form's text read as the section (errors name `shading.*`).
    /// The section's own checks are [`ShadingSphereSection::validate`]'s.
    pub fn from_alias(text: &str) -> Result<ShadingSphereSection, String> {
        let f: AliasForm = toml::from_str(text).map_err(|e| {
            format!(
                "{ALIAS_TABLE}: {}",
                e.message().lines().next().unwrap_or("not a shading scene")
            )
        })?;
        let s = f.shading;
        let chip = match &s.chip {
            None => ChipPreset::GeForce2,
            Some(toml::Value::String(c)) => {
                ChipPreset::parse("shading.chip", c).map_err(|e| e.to_string())?
            }
            Some(v) => {
                return Err(format!(
                    "shading.chip: {v} is not a chip preset's name (known: {})",
                    ChipPreset::NAMES.join(", ")
                ))
            }
        };
        Ok(ShadingSphereSection {
            scene: s.scene,
            image: s.image,
            chip,
            hw: s.hw,
            table: ALIAS_TABLE,
        })
    }

    /// The checks that need no unit: the scene is a built-in shading scene, the image
    /// side is in 2 ..= 4096 and `shading-vertex` has none. Errors name the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let names = SHADING_NAMES;
        if !names.contains(&self.scene.as_str()) {
            let hint = super::suggest::did_you_mean(&self.scene, names, "");
            let hint = if hint.is_empty() {
                String::new()
            } else {
                format!("; {hint}")
            };
            return Err(ConfigError::invalid(
                &self.field("scene"),
                &format!(
                    "unknown shading scene '{}'{hint} (known: {})",
                    self.scene,
                    names.join(", ")
                ),
            ));
        }
        match self.image {
            Some(_) if self.scene == VERTEX => Err(ConfigError::invalid(
                &self.field("image"),
                "shading-vertex lights sphere vertices, it has no image",
            )),
            Some(n) => rtl_model::error::check_range(&self.field("image"), n.into(), 2, 4096),
            None => Ok(()),
        }
    }
}
