//! `render --json`: one object, one shape, for every scene family (the frame's
//! shafts, glare and showcase scenes, the environment-map scenes, the shading scenes
//! and the foundation test scene). Each family's `render` fills a [`RenderJson`] and
//! prints it here, so the families cannot drift apart; what only one family has goes
//! in its own named sub-object (`frame`, `environment`, `shading`, `test`), never in a
//! new top-level field. docs/json.md describes every field; docs/render.schema.json is
//! the same as a JSON Schema, which tests/render_json.rs checks every built-in against.

use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// The version of the shape below; raised when a field changes meaning or goes away.
pub const SCHEMA_VERSION: u32 = 1;

/// The image's size in pixels.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ImageSize {
    pub width: u32,
    pub height: u32,
}

/// The files written (None: not written).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Outputs {
    pub image: Option<String>,
    pub reference: Option<String>,
}

/// One pass of the plan with its predicted and simulated time (None where the
/// family does not time passes one by one).
#[derive(Clone, Debug, Serialize)]
pub struct PassEntry {
    pub name: String,
    pub pipeline: String,
    pub reads: Vec<String>,
    pub writes: Vec<String>,
    pub units: Vec<String>,
    /// The hardware the pass is timed on ("GeForce3", "glare ASIC (…)").
    pub on: Option<String>,
    pub predicted_seconds: Option<f64>,
    pub wall_seconds: Option<f64>,
}

/// The frame's times.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Timing {
    /// Predicted hardware time of the frame (the sum over its passes).
    pub predicted_seconds: Option<f64>,
    /// The GPU preset the GPU passes are timed on.
    pub gpu: Option<String>,
    /// Predicted clocks, where the family counts them for the whole frame.
    pub cycles: Option<u64>,
    /// The clock `cycles` are counted at, in MHz.
    pub clock_mhz: Option<f64>,
    /// Wall time of the simulation (None with `--plan`: nothing ran).
    pub wall_seconds: Option<f64>,
}

/// The scene families.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Family {
    /// Shafts, glare and showcase scenes: rendered through the frame's pass plan.
    Frame,
    /// The environment-map scenes (env-MAP-OBJECT and files with an object).
    Environment,
    /// The shading scenes (shading-*, or a file with a `[shading]` table).
    Shading,
    /// The foundation test scene.
    Test,
}

impl Family {
    /// The name of the family's own sub-object (`frame`, `environment`, …).
    pub fn key(self) -> &'static str {
        match self {
            Family::Frame => "frame",
            Family::Environment => "environment",
            Family::Shading => "shading",
            Family::Test => "test",
        }
    }
}

/// Everything `render --json` prints.
#[derive(Clone, Debug, Serialize)]
pub struct RenderJson {
    pub schema_version: u32,
    pub scene: String,
    pub family: Family,
    /// None for a scene without an image (shading-vertex).
    pub image: Option<ImageSize>,
    pub outputs: Outputs,
    pub passes: Vec<PassEntry>,
    /// The chip the scene elaborates (`frame::chip::elaborate`); null where the family
    /// has no scene to elaborate (shading, test).
    pub chip: Value,
    /// Each pipeline's counters: pipeline → unit → counters.
    pub counters: BTreeMap<String, Value>,
    pub timing: Timing,
    /// Only when `--reference` was given: the error against the f64 reference.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<Value>,
    pub warnings: Value,
    /// The family's own sub-object, under [`Family::key`] (absent with `--plan`).
    #[serde(flatten)]
    pub extra: BTreeMap<&'static str, Value>,
}

impl RenderJson {
    /// An empty report of `scene` in `family`: fill the fields, then [`Self::print`].
    pub fn new(scene: &str, family: Family) -> Self {
        RenderJson {
            schema_version: SCHEMA_VERSION,
            scene: scene.to_string(),
            family,
            image: None,
            outputs: Outputs::default(),
            passes: Vec::new(),
            chip: Value::Null,
            counters: BTreeMap::new(),
            timing: Timing::default(),
            error: None,
            warnings: Value::Array(Vec::new()),
            extra: BTreeMap::new(),
        }
    }

    pub fn image(mut self, width: u32, height: u32) -> Self {
        self.image = Some(ImageSize { width, height });
        self
    }

    /// The paths written.
    pub fn outputs(mut self, image: Option<&Path>, reference: Option<&Path>) -> Self {
        let s = |p: Option<&Path>| p.map(|p| p.display().to_string());
        self.outputs = Outputs {
            image: s(image),
            reference: s(reference),
        };
        self
    }

    /// The family's own sub-object.
    pub fn family_details(mut self, details: Value) -> Self {
        self.extra.insert(self.family.key(), details);
        self
    }

    /// The object as JSON text (pretty).
    pub fn to_text(&self) -> Result<String, String> {
        serde_json::to_string_pretty(self).map_err(|e| e.to_string())
    }

    /// Print the object on stdout.
    pub fn print(&self) -> Result<(), String> {
        println!("{}", self.to_text()?);
        Ok(())
    }
}

/// Serialise for a field (a failure is an error naming nothing the user gave: it
/// cannot happen for the model's own types).
pub fn value<T: Serialize>(v: &T) -> Result<Value, String> {
    serde_json::to_value(v).map_err(|e| e.to_string())
}
