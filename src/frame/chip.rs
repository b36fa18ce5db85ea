//! Whole-chip elaboration: from the scene alone (before any pass runs), which unit
//! instances the chip needs at all, grouped by the scene feature that needs them, and
//! what was left out with the gates it saved. `units --scene FILE` prints it.
//!
//! Gates and RAM bits are each unit's at its registry defaults (`units`), so two
//! scenes' chips compare like for like, and the tables say so; once the frame has run,
//! `render` reports the chip it really elaborated, at the scene's widths
//! (`Frame::elaboration`), as its one chip table.

use super::plan::{environment_scene, shafts_backdrop};
use crate::pipeline::shading::materials::lobe_kind;
use crate::pipeline::shafts::frame::scatters;
use crate::registry;
use crate::scene::clip::clip_needed;
use crate::scene::format::{LightKind, Scene};
use rtl_model::chip_preset::ChipPreset;
use rtl_model::units::blend::Blend;
use rtl_model::UnitSummary;
use serde::Serialize;

/// The scene feature a unit instance serves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub enum Feature {
    /// Objects drawn by the GPU: rasteriser, depth buffer, Lambert colour, blending.
    Objects,
    /// Occluders: the shadow maps.
    Shadows,
    /// Spot lights' light maps.
    LightMaps,
    /// A scattering medium: the sample (and sub-sample) planes.
    Fog,
    /// Objects with a material: the shading units.
    Shading,
    /// An environment map reflected by an object.
    Environment,
    /// A highlight for the glare conditions: one written in the scene, or a specular
    /// material under `glare.shaded_highlights`.
    Highlights,
    /// A glare section: the glare ASIC.
    Glare,
}

impl Feature {
    /// Why a unit of this feature is left out when the scene lacks it.
    pub fn absent_because(self) -> &'static str {
        match self {
            Feature::Objects => "no objects drawn by the GPU",
            Feature::Shadows => "no occluder under a light",
            Feature::LightMaps => "no spot light with a light map",
            Feature::Fog => "no scattering medium (ρ = 0 or K = 0) or no lit light",
            Feature::Shading => "no object with a material",
            Feature::Environment => "no environment map reflected",
            Feature::Highlights => {
                "no highlight to test (none written, no specular material shaded for the glare)"
            }
            Feature::Glare => "no glare section (no glare source, highlight or shaded highlight)",
        }
    }
}

/// One unit instance of the chip.
#[derive(Clone, Debug, Serialize)]
pub struct ChipUnit {
    pub instance: &'static str,
    /// The registry unit it is an instance of.
    pub unit: &'static str,
    pub feature: Feature,
    pub present: bool,
    /// Why it was left out (None when present).
    pub left_out: Option<&'static str>,
    pub gates_nand2: f64,
    pub ram_bits: u64,
}

/// The chip of a scene.
#[derive(Clone, Debug, Serialize)]
pub struct Chip {
    pub units: Vec<ChipUnit>,
    /// The scene's chip preset (its `chip` field).
    pub preset: ChipPreset,
}

impl Chip {
    pub fn present(&self) -> impl Iterator<Item = &ChipUnit> {
        self.units.iter().filter(|u| u.present)
    }
    pub fn left_out(&self) -> impl Iterator<Item = &ChipUnit> {
        self.units.iter().filter(|u| !u.present)
    }
    /// Gates of what is present.
    pub fn gates(&self) -> f64 {
        crate::report::table::gate_total(self.present().map(|u| u.gates_nand2))
    }
    pub fn ram_bits(&self) -> u64 {
        self.present().map(|u| u.ram_bits).sum()
    }
    /// Gates saved by what was left out.
    pub fn gates_saved(&self) -> f64 {
        crate::report::table::gate_total(self.left_out().map(|u| u.gates_nand2))
    }
}

/// Every instance a chip can have: (instance, registry unit, feature).
pub const INSTANCES: &[(&str, &str, Feature)] = &[
    ("clipper", "clipper", Feature::Objects),
    (
        "polygon_interpolator",
        "polygon_interpolator",
        Feature::Objects,
    ),
    (
        "shadow_compare (depth buffer)",
        "shadow_compare",
        Feature::Objects,
    ),
    ("modulate", "modulate", Feature::Objects),
    ("additive_blend", "blend", Feature::Objects),
    (
        "shadow_compare (shadow map)",
        "shadow_compare",
        Feature::Shadows,
    ),
    (
        "projective_texcoord",
        "projective_texcoord",
        Feature::Shadows,
    ),
    (
        "texture_sampler (light map)",
        "texture_sampler",
        Feature::LightMaps,
    ),
    ("texture_sampler (F)", "texture_sampler", Feature::Fog),
    ("texture_sampler (h)", "texture_sampler", Feature::Fog),
    ("additive_blend (J buffer)", "blend", Feature::Fog),
    (
        "cube_map_address (normalisation cube)",
        "cube_map_address",
        Feature::Shading,
    ),
    (
        "texture_sampler (normalisation cube)",
        "texture_sampler",
        Feature::Shading,
    ),
    ("texture_combiner", "texture_combiner", Feature::Shading),
    ("specular_lookup", "specular_lookup", Feature::Shading),
    (
        "texture_sampler (factor textures)",
        "texture_sampler",
        Feature::Shading,
    ),
    (
        "modulate_chain (factor product)",
        "modulate_chain",
        Feature::Shading,
    ),
    (
        "reflection_vector",
        "reflection_vector",
        Feature::Environment,
    ),
    (
        "texture_sampler (environment)",
        "texture_sampler",
        Feature::Environment,
    ),
    ("glare_condition", "glare_condition", Feature::Highlights),
    ("chaos_map", "chaos_map", Feature::Glare),
    ("gaussian_noise", "gaussian_noise", Feature::Glare),
    (
        "polygon_variable_generator",
        "polygon_variable_generator",
        Feature::Glare,
    ),
    (
        "polygon_interpolator (glare)",
        "polygon_interpolator",
        Feature::Glare,
    ),
    (
        "bloom_flare_modulator",
        "bloom_flare_modulator",
        Feature::Glare,
    ),
    ("halo_modulator", "halo_modulator", Feature::Glare),
    ("glare_combiner", "glare_combiner", Feature::Glare),
];

/// Why the scene does not need `instance`, or None when it does: its feature's
/// reason when the feature is absent, else the instance's own.
fn absent(scene: &Scene, instance: &str, feature: Feature) -> Option<&'static str> {
    let backdrop = shafts_backdrop(scene);
    let gpu_objects = backdrop && !scene.objects.is_empty();
    let lit = scene.lights.iter().any(|l| l.intensity > 0.0);
    let fog = backdrop && lit && scatters(&scene.medium);
    let glare = scene.glare.as_ref();
    let present = match feature {
        // An environment-map scene draws its object through the interpolator alone.
        Feature::Objects => {
            gpu_objects || fog || instance == "polygon_interpolator" && environment_scene(scene)
        }
        Feature::Shadows => {
            backdrop && !scene.lights.is_empty() && scene.objects.iter().any(|o| o.occluder)
                || instance == "projective_texcoord" && light_maps(scene)
        }
        Feature::LightMaps => light_maps(scene),
        Feature::Fog => fog,
        Feature::Shading => {
            scene.objects.iter().any(|o| o.material.is_some())
                || glare.is_some_and(|g| g.shaded_highlights.is_some()) && !backdrop
        }
        Feature::Environment => {
            environment_scene(scene)
                || scene
                    .environment
                    .as_ref()
                    .is_some_and(|e| !e.reflectors.is_empty())
        }
        Feature::Highlights => highlights_to_test(scene),
        Feature::Glare => glare.is_some(),
    };
    if !present {
        return Some(feature.absent_because());
    }
    let highlights = highlights_to_test(scene);
    let g = glare;
    let lobe = |kind: &str| {
        scene
            .objects
            .iter()
            .filter_map(|o| o.material)
            .any(|m| lobe_kind(&m) == kind)
    };
    match instance {
        "specular_lookup" if !lobe("lookup") => Some("no Phong or Blinn–Phong lobe"),
        "texture_sampler (factor textures)" | "modulate_chain (factor product)"
            if !lobe("factored") =>
        {
            Some("no factored BRDF")
        }
        "shadow_compare (depth buffer)" if !gpu_objects => Some("no objects drawn by the GPU"),
        "clipper" if !gpu_objects => Some("no objects drawn by the GPU"),
        "clipper" if clip_needed(scene).is_none() => Some(
            "every object inside the near and far planes and the guard band (sample planes cover the viewport only)",
        ),
        "additive_blend (J buffer)" if scene.shafts.subplanes <= 1 => {
            Some("m = 1: no sub-sample planes")
        }
        "chaos_map" if !g.is_some_and(|g| g.sources.iter().any(|s| s.fluctuation.is_some())) => {
            Some("no fluctuating glare source")
        }
        // A highlight that passes the glare conditions becomes a source with halo and
        // flare lines: which ones pass is found per frame, so the chip has both units.
        "gaussian_noise"
            if !g.is_some_and(|g| g.sources.iter().any(|s| s.flare)) && !highlights =>
        {
            Some("no glare source with flare lines, no highlight to test")
        }
        "halo_modulator" if !g.is_some_and(|g| g.sources.iter().any(|s| s.halo)) && !highlights => {
            Some("no glare source with a halo, no highlight to test")
        }
        _ => None,
    }
}

/// Whether the glare conditions have a highlight to test: one written in the scene,
/// or a specular material under `glare.shaded_highlights`.
fn highlights_to_test(scene: &Scene) -> bool {
    scene.glare.as_ref().is_some_and(|g| {
        !g.highlights.is_empty()
            || g.shaded_highlights.is_some()
                && scene
                    .objects
                    .iter()
                    .any(|o| o.material.is_some_and(|m| m.has_specular()))
    })
}

/// Whether a spot light carries a light map (drawn by the shafts passes).
fn light_maps(scene: &Scene) -> bool {
    shafts_backdrop(scene)
        && scene
            .lights
            .iter()
            .any(|l| l.kind == LightKind::Spot && l.light_map.is_some())
}

/// Elaborate the chip of a scene.
pub fn elaborate(scene: &Scene) -> Chip {
    let summaries = registry::summaries();
    // The additive blends (instances named `additive_blend …`) are `blend`'s additive
    // datapath, GL_ONE at 8 bits, not its programmable default.
    let additive = UnitSummary::of(&Blend::additive(8, 8, false, 8).expect("8-bit additive blend"));
    let units = INSTANCES
        .iter()
        .map(|&(instance, unit, feature)| {
            let s = if unit == "blend" && instance.starts_with("additive_blend") {
                Some(&additive)
            } else {
                summaries.iter().find(|s| s.name == unit)
            };
            let left_out = absent(scene, instance, feature);
            ChipUnit {
                instance,
                unit,
                feature,
                present: left_out.is_none(),
                left_out,
                gates_nand2: s.map_or(0.0, |s| s.gates_nand2),
                ram_bits: s.map_or(0, |s| s.ram_bits),
            }
        })
        .collect();
    Chip {
        units,
        preset: scene.chip,
    }
}

/// The report's line on a frame scene's chip preset: its name and the units present
/// whose modes it sets ([`ChipPreset::changes`]). No unit a frame elaborates has a
/// mode that differs between the chips (`rtl_model::chip_preset`: shadow_compare's
/// compare function and texel format are the scene's own state), so at `nv2a` the line
/// says that the frame renders as at `geforce2`.
pub fn preset_line(preset: ChipPreset, present_units: &[&str]) -> String {
    let mut changed: Vec<&str> = present_units
        .iter()
        .copied()
        .filter(|u| preset.changes(u))
        .collect();
    changed.dedup();
    if preset.is_default() {
        format!("chip preset: {preset} (the project's defaults)")
    } else if changed.is_empty() {
        format!(
            "chip preset: {preset} (no unit of this frame has a mode that differs from the GeForce2's: the frame renders as under geforce2)"
        )
    } else {
        format!(
            "chip preset: {preset} (its modes in {})",
            changed.join(", ")
        )
    }
}

/// The chip as text: what is present, then what was left out and why.
pub fn chip_table(chip: &Chip) -> String {
    let rows: Vec<Vec<String>> = chip
        .units
        .iter()
        .map(|u| {
            vec![
                u.instance.to_string(),
                format!("{:?}", u.feature),
                match u.left_out {
                    None => "present".to_string(),
                    Some(why) => format!("left out: {why}"),
                },
                format!("{:.0}", u.gates_nand2),
                u.ram_bits.to_string(),
            ]
        })
        .collect();
    let mut s = crate::report::table::text_table(
        &[
            "unit instance",
            "feature",
            "elaborated",
            "gates_nand2 (defaults)",
            "ram_bits (defaults)",
        ],
        &rows,
    );
    let present: Vec<&str> = chip.present().map(|u| u.unit).collect();
    s.push_str(&preset_line(chip.preset, &present));
    s.push('\n');
    s.push_str(&format!(
        "chip: {} of {} unit instances, {:.0} NAND2 gates, {} RAM/ROM bits at the registry's default widths; left out {} ({:.0} gates saved)\n",
        chip.present().count(),
        chip.units.len(),
        chip.gates(),
        chip.ram_bits(),
        chip.left_out().count(),
        chip.gates_saved()
    ));
    s
}

/// The chip as `render --plan --json` gives it: every instance, present or left out
/// with why, at the registry's default widths (`widths` says so), and the totals.
pub fn defaults_json(chip: &Chip) -> serde_json::Value {
    serde_json::json!({
        "widths": "registry defaults",
        "preset": chip.preset,
        "units": chip.units,
        "gates_nand2": chip.gates(),
        "ram_bits": chip.ram_bits(),
        "gates_saved": chip.gates_saved(),
    })
}

/// The chip a render really elaborated (each pass's units at the scene's widths, and
/// what was left out with what it saved), as `render --json` gives it.
pub fn elaborated_json(
    units: &[crate::report::elaboration::Elaborated],
    preset: ChipPreset,
) -> serde_json::Value {
    let present = units.iter().filter_map(|u| u.summary.as_ref());
    serde_json::json!({
        "widths": "scene",
        "preset": preset,
        "units": units,
        "gates_nand2": crate::report::table::gate_total(present.clone().map(|s| s.gates_nand2)),
        "ram_bits": present.map(|s| s.ram_bits).sum::<u64>(),
        "gates_saved": crate::report::table::gate_total(
            units.iter().filter(|u| u.left_out.is_some()).map(|u| u.gates_saved),
        ),
    })
}
