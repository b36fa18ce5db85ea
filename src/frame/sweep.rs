//! `sweep` on a frame scene: a scene whose frame runs more than one pipeline
//! (`night-street`, `shaded-metal`, `shaded-dielectric`, `street-light`, a file like
//! them). Any width of any pipeline the frame runs can be swept; each value's scene is
//! rendered through the frame as `render` renders it and compared with the frame's
//! composed f64 reference (`reproduce::frame_error_and_reference`), so the error is
//! the whole picture's, every pass's sources included.
//!
//! A parameter is named as `PIPELINE.FIELD` (`shafts.planes`, `glare.fb_bits`,
//! `environment.side`, `shading.cube_face`) or by its field alone when only one
//! pipeline of the scene has a field of that name (`planes`); a name two pipelines
//! share (`fb_bits` on a scene with shafts and glare) is refused naming both.
//!
//! A row holds the frame's error (mean |Δ|, RMS, max in 8-bit levels over every pixel
//! and channel), the predicted frame time (the sum over passes, `render`'s), the
//! simulation's wall time, and the gates and RAM bits of every unit the frame's
//! pipelines elaborated at that value. The CSV, plot, resume and shards are those of
//! the other sweeps (`report::sweep_out`).

use super::plan::frame_pipelines;
use super::reproduce::frame_error_and_reference;
use super::run::render;
use crate::pipeline::glare::sweep::{apply as apply_glare, get as apply_get, GLARE_PARAMS};
use crate::pipeline::shafts::sweep::{Param as ShaftsParam, Value as ShaftsValue};
use crate::report::metrics::error_stats;
use crate::report::progress::try_map_with_progress;
use crate::report::resume::Journal;
use crate::report::shard::{Shard, SweepId};
use crate::report::sweep_out::{parse_int_values, run_sweep, sweep_table, SweepRow};
use crate::scene::format::Scene;
use crate::scene::shading_hw::SHADING_HW_FIELDS;
use std::path::Path;

/// Whether `scene` is a frame scene for `sweep` and `attribute`: its frame runs the
/// widths of more than one pipeline (an environment-map scene of the thesis and a
/// single pipeline's scene keep their own sweep and attribution).
pub fn is_frame_scene(scene: &Scene) -> Result<bool, String> {
    Ok(frame_pipelines(scene).map_err(|e| e.to_string())?.len() > 1)
}

/// Whether `sweep` takes the scene through the environment-map sweep: it has an
/// environment and no glare.
pub fn environment_sweep(scene: &Scene) -> bool {
    scene.environment.is_some() && scene.glare.is_none()
}

/// The path `sweep` takes, by what the scene holds and the parameter (never by the
/// scene's name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepPath {
    /// The foundation test scene: nothing to sweep (refused).
    TestScene,
    /// A shading sphere's width (`pipeline::shading::sweep`; with `--attribute`,
    /// `pipeline::shading::attributed_sweep`).
    Shading,
    /// An architecture parameter of the clocked chip (`frame::chip_sweep`).
    Chip,
    /// `--attribute` on a scene of lights and objects (refused).
    AttributeRefused,
    /// An environment-map scene's own parameters (`pipeline::envmap::sweep`).
    Environment,
    /// A scene of several pipelines, through the frame.
    Frame,
    /// A glare scene through the glare pass (over its shafts backdrop, if any).
    Glare,
    /// A shafts scene.
    Shafts,
}

/// [`SweepPath`] of a loaded scene, `--param` and `--attribute`.
pub fn sweep_path(scene: &Scene, param: &str, attribute: bool) -> Result<SweepPath, String> {
    use crate::scene::format::SceneKind;
    Ok(match scene.kind() {
        SceneKind::Test => SweepPath::TestScene,
        SceneKind::ShadingSphere(_) => SweepPath::Shading,
        SceneKind::Frame if crate::chip::params::ChipParam::from_name(param).is_some() => {
            SweepPath::Chip
        }
        SceneKind::Frame if attribute => SweepPath::AttributeRefused,
        SceneKind::Frame if environment_sweep(scene) => SweepPath::Environment,
        SceneKind::Frame if is_frame_scene(scene)? => SweepPath::Frame,
        SceneKind::Frame if scene.glare.is_some() => SweepPath::Glare,
        SceneKind::Frame => SweepPath::Shafts,
    })
}

/// One sweepable field of a frame scene: its pipeline and qualified name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameParam {
    pub pipeline: &'static str,
    /// The field's name within its pipeline (`planes`, `fb_bits`, `side`).
    pub field: &'static str,
}

impl FrameParam {
    /// `shafts.planes`, `glare.fb_bits`, `environment.side`, `shading.cube_face`.
    pub fn qualified(&self) -> String {
        format!("{}.{}", self.pipeline, self.field)
    }

    /// The param of a qualified name in [`FRAME_PARAMS`].
    pub fn of_qualified(name: &str) -> Option<FrameParam> {
        FRAME_PARAMS
            .iter()
            .find(|(_, _, q)| *q == name)
            .map(|&(pipeline, field, _)| FrameParam { pipeline, field })
    }

    /// The qualified name as a static string (from [`FRAME_PARAMS`]).
    pub fn qualified_static(&self) -> &'static str {
        FRAME_PARAMS
            .iter()
            .find(|(p, f, _)| *p == self.pipeline && *f == self.field)
            .map_or("", |(_, _, q)| q)
    }

    /// This field's value in `s` (the shading defaults when `[shading_hw]` is absent).
    pub fn get(&self, s: &Scene) -> Result<u32, String> {
        match self.pipeline {
            "shafts" => Ok(ShaftsParam::from_name(self.field)?.get(&s.shafts)),
            "glare" => {
                let g = &s.glare.as_ref().ok_or("scene: no [glare] section")?.hw;
                apply_get(g, self.field)
            }
            "environment" => Ok(s
                .environment
                .as_ref()
                .ok_or("scene: no [environment] section")?
                .side),
            _ => {
                let hw = s.shading_hw.unwrap_or_default();
                Ok(match self.field {
                    "cube_face" => hw.cube_face,
                    "lookup_log2" => hw.lookup_log2,
                    "factor_size" => hw.factor_size,
                    _ => hw.factor_bits,
                })
            }
        }
    }

    /// Set this field of `s` to `v` (no validation: the caller validates the scene).
    pub fn apply(&self, s: &mut Scene, v: u32) -> Result<(), String> {
        match self.pipeline {
            "shafts" => {
                let p = ShaftsParam::from_name(self.field)?;
                p.apply(&mut s.shafts, ShaftsValue::One(v))
            }
            "glare" => {
                let g = s
                    .glare
                    .as_mut()
                    .ok_or("scene: it has no [glare] section to sweep")?;
                apply_glare(&mut g.hw, self.field, v)
            }
            "environment" => {
                let e = s
                    .environment
                    .as_mut()
                    .ok_or("scene: it has no [environment] section to sweep")?;
                e.side = v;
                Ok(())
            }
            "shading" => s
                .shading_hw
                .get_or_insert_with(Default::default)
                .set(self.field, v),
            other => Err(format!("internal: no pipeline '{other}'")),
        }
    }
}

/// Every frame param by its qualified name: (pipeline, field, `pipeline.field`).
/// Shafts' pair-valued `mesh` and `h_texels` are not among them: a frame sweep's
/// values are whole numbers. A test checks this against each pipeline's own list
/// ([`pipeline_param_names`]).
pub const FRAME_PARAMS: &[(&str, &str, &str)] = &[
    ("shafts", "planes", "shafts.planes"),
    ("shafts", "subplanes", "shafts.subplanes"),
    ("shafts", "texel_bits", "shafts.texel_bits"),
    ("shafts", "fb_bits", "shafts.fb_bits"),
    ("shafts", "weight_bits", "shafts.weight_bits"),
    ("shafts", "coord_frac_bits", "shafts.coord_frac_bits"),
    ("shafts", "shadow_resolution", "shafts.shadow_resolution"),
    ("shafts", "shadow_depth_bits", "shafts.shadow_depth_bits"),
    ("shafts", "f_texels", "shafts.f_texels"),
    ("shafts", "light_map_texels", "shafts.light_map_texels"),
    ("shafts", "acc_int_bits", "shafts.acc_int_bits"),
    ("shafts", "acc_frac_bits", "shafts.acc_frac_bits"),
    ("shafts", "recip_index_bits", "shafts.recip_index_bits"),
    ("shafts", "recip_entry_bits", "shafts.recip_entry_bits"),
    ("shafts", "newton_frac_bits", "shafts.newton_frac_bits"),
    ("shading", "cube_face", "shading.cube_face"),
    ("shading", "lookup_log2", "shading.lookup_log2"),
    ("shading", "factor_size", "shading.factor_size"),
    ("shading", "factor_bits", "shading.factor_bits"),
    ("environment", "side", "environment.side"),
    ("glare", "shape_log2", "glare.shape_log2"),
    ("glare", "shape_bits", "glare.shape_bits"),
    ("glare", "falloff_log2", "glare.falloff_log2"),
    ("glare", "falloff_bits", "glare.falloff_bits"),
    ("glare", "weight_bits", "glare.weight_bits"),
    ("glare", "coord_frac_bits", "glare.coord_frac_bits"),
    ("glare", "noise_bits", "glare.noise_bits"),
    ("glare", "fb_bits", "glare.fb_bits"),
    ("glare", "radial", "glare.radial"),
];

/// Every field a frame sweep can change on `scene`, by the pipelines its frame runs,
/// in [`FRAME_PARAMS`]' order.
pub fn frame_params(scene: &Scene) -> Result<Vec<FrameParam>, String> {
    let pipelines = frame_pipelines(scene).map_err(|e| e.to_string())?;
    Ok(FRAME_PARAMS
        .iter()
        .filter(|(p, _, _)| pipelines.contains(p))
        .map(|&(pipeline, field, _)| FrameParam { pipeline, field })
        .collect())
}

/// The qualified name of every param of each pipeline's own list (shafts' single-
/// valued `sweep` params, the shading widths, the map's side, the glare widths): what
/// [`FRAME_PARAMS`] must hold, in its order.
pub fn pipeline_param_names() -> Vec<String> {
    let shafts = ShaftsParam::ALL
        .iter()
        .filter(|p| !p.is_pair())
        .map(|p| format!("shafts.{}", p.name()));
    let shading = SHADING_HW_FIELDS.iter().map(|f| format!("shading.{f}"));
    let glare = GLARE_PARAMS.iter().map(|f| format!("glare.{f}"));
    shafts
        .chain(shading)
        .chain(std::iter::once("environment.side".to_string()))
        .chain(glare)
        .collect()
}

/// `param` as one of `scene`'s frame params (module notes); errors name `param` and
/// list the valid names.
pub fn resolve_param(scene: &Scene, param: &str) -> Result<FrameParam, String> {
    let all = frame_params(scene)?;
    let norm = param.trim().replace('-', "_");
    let norm = norm
        .strip_prefix("glare.hw.")
        .map(|f| format!("glare.{f}"))
        .or_else(|| {
            norm.strip_prefix("envmap.")
                .map(|f| format!("environment.{f}"))
        })
        .unwrap_or(norm);
    let hits: Vec<&FrameParam> = all
        .iter()
        .filter(|p| p.qualified() == norm || p.field == norm)
        .collect();
    match hits.as_slice() {
        [one] => Ok((*one).clone()),
        [] => {
            let names: Vec<String> = all.iter().map(FrameParam::qualified).collect();
            // The nearest qualified name, or the nearest field (then its qualified
            // name): "plane" → shafts.planes.
            let near = crate::report::suggest::nearest(&norm, names.iter().map(String::as_str))
                .map(str::to_string)
                .or_else(|| {
                    crate::report::suggest::nearest(&norm, all.iter().map(|p| p.field))
                        .and_then(|f| all.iter().find(|p| p.field == f))
                        .map(FrameParam::qualified)
                });
            Err(format!(
                "param: '{param}' is not a width of this frame's pipelines{} (valid: {})",
                near.map_or(String::new(), |n| format!("; did you mean {n}?")),
                names.join(", ")
            ))
        }
        many => Err(format!(
            "param: '{param}' names a field of several pipelines of this frame; say which: {}",
            many.iter()
                .map(|p| p.qualified())
                .collect::<Vec<_>>()
                .join(" or ")
        )),
    }
}

/// The scene of each value, validated: an invalid value is an error naming the field
/// and the value, before anything runs.
pub fn frame_scenes(base: &Scene, p: &FrameParam, values: &[u32]) -> Result<Vec<Scene>, String> {
    values
        .iter()
        .map(|&v| {
            let mut s = base.clone();
            p.apply(&mut s, v)
                .map_err(|e| format!("{e} (value {} = {v})", p.qualified()))?;
            s.validate()
                .map_err(|e| format!("{e} (value {} = {v})", p.qualified()))?;
            Ok(s)
        })
        .collect()
}

/// One row: render `s` through its frame and compare it with the composed reference;
/// `param` (when the row is a sweep's) names the swept field and gives its value.
pub fn frame_row(s: &Scene, param: Option<&FrameParam>) -> Result<SweepRow, String> {
    let f = render(s).map_err(|e| e.to_string())?;
    let (_, reference) = frame_error_and_reference(s, &f)?;
    let st = error_stats(&f.fb.levels(), &reference).map_err(|e| e.to_string())?;
    let units = f.elaboration();
    let summaries = units.iter().filter_map(|u| u.summary.as_ref());
    Ok(SweepRow {
        param: param.map_or_else(String::new, FrameParam::qualified),
        value: param.map_or(Ok(0), |p| p.get(s))?,
        mean_abs_levels: st.mean_abs,
        rms_levels: st.rms,
        max_levels: st.max,
        predicted_hw_seconds: f.predicted_seconds(),
        wall_seconds: f.wall_seconds,
        gates_nand2: summaries.clone().map(|u| u.gates_nand2).sum(),
        ram_bits: summaries.map(|u| u.ram_bits).sum(),
    })
}

fn frame_rows(
    scenes: &[Scene],
    p: &FrameParam,
    only: Option<Shard>,
    journal: &mut Journal<SweepRow>,
) -> Result<(), String> {
    let todo = journal.pending(scenes, only);
    try_map_with_progress(&todo, &format!("sweep {}", p.qualified()), |&(i, s)| {
        let row = frame_row(s, Some(p))?;
        journal.record(i, row)
    })?;
    Ok(())
}

fn title(base: &Scene, param: &str) -> String {
    format!(
        "{}: frame error and run time against {param}",
        base.short_name()
    )
}

/// The CLI: the whole sweep into `out/sweep_<param>.csv` and `.png` (`param`
/// qualified, e.g. `sweep_shafts.planes.csv`), or with `shard` only its share, for
/// `sweep merge`; continuing with `resume`.
pub fn frame_sweep_cli(
    scene: &Scene,
    scene_arg: &str,
    param: &str,
    values: &str,
    out: &Path,
    shard: Option<Shard>,
    resume: bool,
) -> Result<(), String> {
    let p = resolve_param(scene, param)?;
    let values = parse_int_values(values)?;
    // Every value is checked before a journal removes an old CSV.
    let scenes = frame_scenes(scene, &p, &values)?;
    let name = p.qualified();
    let id = SweepId::of_scene(
        "frame",
        scene,
        (scene.image.width, scene.image.height),
        scene_arg,
        &name,
        &values,
        title(scene, &name),
    )?;
    let Some((rows, csv, png)) = run_sweep(out, &id, shard, resume, |only, journal| {
        frame_rows(&scenes, &p, only, journal)
    })?
    else {
        return Ok(());
    };
    println!(
        "sweep {name} on {} (the whole frame against its composed reference): wrote {} and {}",
        scene.name,
        csv.display(),
        png.display()
    );
    print!("{}", sweep_table(&name, &rows));
    Ok(())
}
