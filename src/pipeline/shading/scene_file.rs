//! A shading sphere scene built: a scene's `[shading_sphere]` section
//! (`scene::shading_sphere`) turned into the shading path's point at its widths, and
//! the `[shading]` file form, the section's alias, which `scene NAME` prints for a
//! `shading-*` scene and `optimize` writes as `best.toml` for one:
//!
//! ```toml
//! [shading]
//! scene = "shading-blinn_phong"   # a built-in shading scene (`sweep`'s names)
//! image = 64                      # the sphere view's side in pixels (default 256)
//! chip = "nv2a"                   # the chip preset (default "geforce2")
//!
//! [shading.hw]                    # the scene's widths (`sweep`'s names); a width
//! cube_face = 32                  # not given keeps its GeForce default
//! lookup_log2 = 7
//! ```
//!
//! Every field is checked before anything renders, each error naming it
//! (`shading.scene`, `shading.image`, `shading.chip`, `shading.hw.<width>`, or the same
//! under `shading_sphere.` in the section form); an unknown key is refused.

use super::sweep::{
    measure_point, params_of, shading_reference, sweep_view, ShadingMeasure, ShadingPoint,
    ShadingScene,
};
use crate::scene::shading_sphere::ShadingSphereSection;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The sphere view's side when the file gives none (the `shading-brdfs` view).
pub const DEFAULT_IMAGE: u32 = crate::scene::shading_sphere::DEFAULT_IMAGE;

/// A shading scene at given widths: what a file (or a `shading-*` name, at the
/// defaults) describes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingFile {
    pub point: ShadingPoint,
    /// The sphere view's side in pixels; None for `shading-vertex` (no image).
    pub image: Option<u32>,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct FileForm {
    shading: Section,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct Section {
    scene: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    image: Option<u32>,
    /// The chip preset's name ([`ChipPreset`]); left out: the GeForce2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    chip: Option<toml::Value>,
    #[serde(default)]
    hw: BTreeMap<String, u32>,
}

impl ShadingFile {
    /// A built-in `shading-*` scene at its defaults (errors name `scene`).
    pub fn builtin(name: &str) -> Result<ShadingFile, String> {
        let sc = ShadingScene::parse(name)?;
        let point = ShadingPoint::new(&sc, &[])?;
        Ok(ShadingFile {
            point,
            image: (sc != ShadingScene::Vertex).then_some(DEFAULT_IMAGE),
        })
    }

    /// A scene's `[shading_sphere]` section (or its `[shading]` alias) built: the
    /// scene's name, image and chip as validation checked them, each width set on
    /// the scene's units. An error names the field under the section's table
    /// (`shading_sphere.hw.cube_face`, or `shading.hw.cube_face` in the alias form).
    pub fn from_section(s: &ShadingSphereSection) -> Result<ShadingFile, String> {
        s.validate().map_err(|e| e.to_string())?;
        let table = s.table;
        let sc = ShadingScene::parse(&s.scene)
            .map_err(|e| e.replacen("scene:", &format!("{table}.scene:"), 1))?;
        let valid = params_of(&sc).join(", ");
        let mut widths: Vec<(&str, u32)> = Vec::new();
        for (k, v) in &s.hw {
            if !params_of(&sc).contains(&k.as_str()) {
                return Err(format!(
                    "{table}.hw.{k}: not a width of {} (valid: {valid})",
                    sc.name()
                ));
            }
            widths.push((k.as_str(), *v));
        }
        // Set one width at a time: an invalid value is named by its key.
        let mut so_far: Vec<(&str, u32)> = Vec::new();
        for (k, v) in &widths {
            so_far.push((k, *v));
            ShadingPoint::new(&sc, &so_far).map_err(|e| format!("{table}.hw.{k}: {e}"))?;
        }
        let point = ShadingPoint::new(&sc, &widths).map_err(|e| format!("{table}.hw: {e}"))?;
        Ok(ShadingFile {
            point: point.on_chip(s.chip),
            image: s.side(),
        })
    }

    /// A shading sphere scene's section built ([`ShadingFile::from_section`]); an
    /// error for a scene of another kind.
    pub fn from_scene(scene: &crate::scene::format::Scene) -> Result<ShadingFile, String> {
        match &scene.shading_sphere {
            Some(s) => ShadingFile::from_section(s),
            None => Err(format!(
                "scene: '{}' is not a shading sphere scene (it has no [shading_sphere] section)",
                scene.name
            )),
        }
    }

    /// Every width of the point's path, by name.
    fn widths(&self) -> BTreeMap<String, u32> {
        self.point
            .widths()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect()
    }

    /// The section that builds this (every width of the point's path written out).
    pub fn to_section(&self) -> ShadingSphereSection {
        ShadingSphereSection {
            image: self.image,
            chip: self.point.chip(),
            hw: self.widths(),
            ..ShadingSphereSection::builtin(&self.point.scene().name())
        }
    }

    /// The `[shading]` file form's text, checked (errors name `shading.*`).
    pub fn parse(text: &str) -> Result<ShadingFile, String> {
        let s = ShadingSphereSection::from_alias(text)?;
        ShadingFile::from_section(&s)
    }

    /// The file form (`header`, comment lines, first), every width of the point's
    /// path written out.
    pub fn to_toml(&self, header: &str) -> Result<String, String> {
        let f = FileForm {
            shading: Section {
                scene: self.point.scene().name(),
                image: self.image,
                chip: (!self.point.chip().is_default())
                    .then(|| toml::Value::String(self.point.chip().to_string())),
                hw: self.widths(),
            },
        };
        let body =
            toml::to_string_pretty(&f).map_err(|e| format!("shading: cannot write TOML: {e}"))?;
        Ok(format!("{header}\n{body}"))
    }
}

/// `render --scene` of a shading scene: the sweep's render of the point on its view
/// against the sweep's reference; the sphere's grey levels to `out` (and the
/// reference's to `reference`), the error, gates, RAM bits and predicted time
/// printed (`json`: as one JSON object). `shading-vertex` has no image: nothing is
/// written. `plan_only`: the configuration only.
pub fn render_cli(
    f: &ShadingFile,
    out: &Path,
    json: bool,
    reference: Option<&Path>,
    plan_only: bool,
) -> Result<(), String> {
    let name = f.point.scene().name();
    let widths = f
        .point
        .widths()
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect::<Vec<_>>()
        .join(" ");
    if plan_only {
        return print_plan(f, &name, &widths, json);
    }
    let size = f.image.unwrap_or(DEFAULT_IMAGE);
    let view = sweep_view(size);
    let r = shading_reference(&f.point, &view)?;
    let m = measure_point(&f.point, &view, &r)?;
    let grey = |v: &[f64]| v.iter().map(|&x| [x; 3]).collect::<Vec<_>>();
    let mut wrote = Vec::new();
    if f.image.is_some() {
        crate::report::image_out::levels_png(&grey(&m.levels), size, size, out)?;
        wrote.push(out.display().to_string());
        if let (Some(p), super::sweep::ShadingReference::Image { levels, .. }) = (reference, &r) {
            crate::report::image_out::levels_png(&grey(levels), size, size, p)
                .map_err(|e| e.replacen("out:", "reference:", 1))?;
            wrote.push(p.display().to_string());
        }
    }
    if json {
        return print_json(f, &name, &m, &r, out, reference);
    }
    println!(
        "shading scene {name} ({}): {widths}",
        f.image
            .map_or("vertices, no image".to_string(), |s| format!("{s}x{s}"))
    );
    println!("  {}", chip_line(&f.point));
    println!(
        "  error against the reference (8-bit levels): mean |Δ| {:.3}, rms {:.3}, max {:.3}",
        m.mean_abs_levels, m.rms_levels, m.max_levels
    );
    println!(
        "  gates {:.0} NAND2, RAM bits {}, predicted {:.6} s (GeForce3), wall {:.3} s",
        m.gates_nand2, m.ram_bits, m.predicted_hw_seconds, m.wall_seconds
    );
    if wrote.is_empty() {
        println!("  no image written (shading-vertex has none)");
    } else {
        println!("  wrote {}", wrote.join(", "));
    }
    Ok(())
}

/// `render --plan-only` of a shading scene: its widths and chip line (`json`: the
/// render's object with nothing rendered, docs/json.md).
fn print_plan(f: &ShadingFile, name: &str, widths: &str, json: bool) -> Result<(), String> {
    if json {
        let mut j = crate::report::render_json::RenderJson::new(
            name,
            crate::report::render_json::Family::Shading,
        );
        if let Some(side) = f.image {
            j = j.image(side, side);
        }
        return j.print();
    }
    println!("shading scene {name}: {widths}");
    println!("  {}", chip_line(&f.point));
    Ok(())
}

/// `render --json` of a shading scene: the render's object with the widths, chip,
/// error, gates, RAM bits and times of `m` (the files named where written).
fn print_json(
    f: &ShadingFile,
    name: &str,
    m: &ShadingMeasure,
    r: &super::sweep::ShadingReference,
    out: &Path,
    reference: Option<&Path>,
) -> Result<(), String> {
    use crate::report::render_json::{Family, RenderJson, Timing};
    let error = serde_json::json!({
        "mean_abs_levels": m.mean_abs_levels,
        "rms_levels": m.rms_levels,
        "max_levels": m.max_levels,
    });
    let written = f.image.is_some();
    let ref_written =
        written && reference.is_some() && matches!(r, super::sweep::ShadingReference::Image { .. });
    let mut j = RenderJson::new(name, Family::Shading)
        .outputs(written.then_some(out), reference.filter(|_| ref_written))
        .family_details(serde_json::json!({
            "widths": f.point.widths().into_iter().collect::<BTreeMap<_, _>>(),
            "chip_preset": f.point.chip().name(),
            "units_the_chip_changes": f.point.units_the_chip_changes(),
            "error_levels": error,
            "gates_nand2": m.gates_nand2,
            "ram_bits": m.ram_bits,
        }));
    if let Some(side) = f.image {
        j = j.image(side, side);
    }
    j.timing = Timing {
        predicted_seconds: Some(m.predicted_hw_seconds),
        gpu: Some("GeForce3".into()),
        cycles: None,
        clock_mhz: None,
        wall_seconds: Some(m.wall_seconds),
    };
    if reference.is_some() {
        j.error = Some(error);
    }
    j.print()
}

/// The report's line on the chip preset: its name and the path's units whose modes it
/// sets (docs/conformance.md, "Where they differ").
pub fn chip_line(point: &ShadingPoint) -> String {
    let chip = point.chip();
    let changed = point.units_the_chip_changes();
    if chip.is_default() {
        format!("chip preset: {chip} (the project's defaults)")
    } else if changed.is_empty() {
        format!("chip preset: {chip} (no unit of this path has a mode that differs from the GeForce2's)")
    } else {
        let modes: Vec<String> = chip
            .modes()
            .into_iter()
            .filter(|m| changed.contains(&m.unit))
            .map(|m| format!("{}.{} = {}", m.unit, m.field, m.value))
            .collect();
        format!("chip preset: {chip} ({})", modes.join(", "))
    }
}
