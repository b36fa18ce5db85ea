//! The pass list of a frame, as data: which passes run, in which order, what each
//! reads and writes of the frame's shared state, and which units it uses.
//! `render --plan` prints it; [`super::chip`] and the time model sum over it.
//!
//! The order follows the data: the camera depth pass first (every later pass
//! depth-tests against it); then the object pass of the shading units and environment
//! reflections (objects with a material, into the framebuffer); per light its shadow
//! map, the Lambert objects it lights and its sample planes (added over everything,
//! depth-tested, so the fog in front of a shaded object covers it too); last the glare
//! pass over the finished picture (highlight detection → glare conditions →
//! bloom/halo/flare → combiner).

use crate::pipeline::shafts::frame::{passes as shafts_passes, Prepared, ShaftsPass};
use crate::pipeline::shafts::host::prepare_scene;
use crate::pipeline::shafts::prepare::DEFAULT_EXPOSURE;
use crate::scene::format::Scene;
use crate::scene::glare::Background;
use rtl_model::ConfigError;
use serde::Serialize;

/// What a pass does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Step {
    /// The foundation test scene's fixed passes (`render --scene test`).
    TestScene,
    /// An environment-map scene of the thesis: background and object through the
    /// envmap pipeline.
    EnvironmentScene,
    /// One pass of the light-shafts pipeline.
    Shafts(ShaftsPass),
    /// Objects with a material through the shading units (and, for reflectors, the
    /// environment-map units) into the framebuffer the shafts passes continue.
    ShadedObjects,
    /// Objects through the shading units over the glare pass's own background (a glare
    /// scene whose picture is not drawn by the shafts pipeline).
    ShadedHighlights,
    /// The glare pass.
    Glare,
}

/// One planned pass.
#[derive(Clone, Debug, Serialize)]
pub struct Pass {
    pub step: Step,
    pub name: String,
    pub pipeline: &'static str,
    pub reads: Vec<String>,
    pub writes: Vec<String>,
    pub units: Vec<&'static str>,
}

/// The frame's passes, and the host preparation the shafts passes need.
pub struct Plan {
    pub passes: Vec<Pass>,
    /// The shafts pipeline's host set-up (tessellation, light maps, plane range), when
    /// a shafts pass is planned.
    pub prepared: Option<Prepared>,
}

/// Whether the shafts pipeline draws the picture: a scene without a glare section, or
/// one whose glare background is `shafts`.
pub fn shafts_backdrop(scene: &Scene) -> bool {
    match &scene.glare {
        None => true,
        Some(g) => g.background == Background::Shafts,
    }
}

/// Whether the scene has an object the object pass draws (a material or a
/// reflector).
pub fn has_shaded_objects(scene: &Scene) -> bool {
    (0..scene.objects.len()).any(|i| scene.shaded_object(i))
}

/// Whether the scene is an environment-map scene of the thesis (its object drawn by
/// the envmap pipeline alone).
pub fn environment_scene(scene: &Scene) -> bool {
    scene
        .environment
        .as_ref()
        .is_some_and(|e| e.object.is_some())
}

/// The plan of a scene (`test`: the foundation test scene). Host preparation errors
/// name the scene field.
pub fn plan(scene: &Scene) -> Result<Plan, ConfigError> {
    let mut passes = Vec::new();
    let mut prepared = None;
    if environment_scene(scene) {
        passes.push(Pass {
            step: Step::EnvironmentScene,
            name: "environment (background, thesis object)".into(),
            pipeline: "envmap",
            reads: vec!["environment map (prefiltered voxel map or its 2D slice)".into()],
            writes: vec!["framebuffer".into()],
            units: vec![
                "polygon_interpolator",
                "reflection_vector",
                "texture_sampler (environment)",
            ],
        });
        return Ok(Plan { passes, prepared });
    }
    if shafts_backdrop(scene) {
        let (p, _) = prepare_scene(&strip_glare(scene), DEFAULT_EXPOSURE)?;
        for sp in shafts_passes(&p) {
            passes.push(shafts_pass(&p, sp));
            if sp == ShaftsPass::Depth && has_shaded_objects(scene) {
                passes.push(shaded_objects());
            }
        }
        prepared = Some(p);
    } else if scene
        .glare
        .as_ref()
        .is_some_and(|g| g.shaded_highlights.is_some())
    {
        passes.push(Pass {
            step: Step::ShadedHighlights,
            name: "objects (shading units)".into(),
            pipeline: "shading",
            reads: vec![
                "normalisation cube map".into(),
                "factor textures / specular lookup".into(),
            ],
            writes: vec!["glare background".into(), "highlights".into()],
            units: SHADING_UNITS.to_vec(),
        });
    }
    if scene.glare.is_some() {
        passes.push(Pass {
            step: Step::Glare,
            name: "glare".into(),
            pipeline: "glare",
            reads: vec![
                "framebuffer".into(),
                "highlights".into(),
                "glare tables".into(),
            ],
            writes: vec!["framebuffer".into()],
            units: GLARE_UNITS.to_vec(),
        });
    }
    Ok(Plan { passes, prepared })
}

/// The pipelines whose widths a scene's frame uses, each once, in plan order:
/// "shafts", "shading" (objects with a material), "environment" (reflectors of an
/// environment map), "glare". An environment-map scene of the thesis is
/// "environment" alone.
pub fn frame_pipelines(scene: &Scene) -> Result<Vec<&'static str>, ConfigError> {
    let mut v: Vec<&'static str> = Vec::new();
    let mut add = |p: &'static str| {
        if !v.contains(&p) {
            v.push(p);
        }
    };
    let has_material = scene.objects.iter().any(|o| o.material.is_some());
    for pass in plan(scene)?.passes {
        match pass.step {
            Step::TestScene => {}
            Step::EnvironmentScene => add("environment"),
            Step::Shafts(_) => add("shafts"),
            Step::ShadedObjects | Step::ShadedHighlights => {
                if has_material {
                    add("shading");
                }
                if scene
                    .environment
                    .as_ref()
                    .is_some_and(|e| !e.reflectors.is_empty())
                {
                    add("environment");
                }
            }
            Step::Glare => add("glare"),
        }
    }
    Ok(v)
}

/// The plan of the foundation test scene: its passes are fixed.
pub fn test_scene_plan() -> Plan {
    let p = |name: &str, reads: &[&str], writes: &[&str], units: &[&'static str]| Pass {
        step: Step::TestScene,
        name: name.into(),
        pipeline: "test scene",
        reads: reads.iter().map(|s| s.to_string()).collect(),
        writes: writes.iter().map(|s| s.to_string()).collect(),
        units: units.to_vec(),
    };
    Plan {
        passes: vec![
            p(
                "shadow map (occluder)",
                &["occluder"],
                &["shadow map"],
                &["polygon_interpolator", "shadow_compare"],
            ),
            p(
                "floor (ambient + spot)",
                &["checker texture", "light map", "shadow map"],
                &["framebuffer"],
                &[
                    "polygon_interpolator",
                    "projective_texcoord",
                    "texture_sampler",
                    "shadow_compare",
                    "modulate",
                    "additive_blend",
                ],
            ),
        ],
        prepared: None,
    }
}

/// The scene as the shafts pipeline sees it (its glare is another pass's).
pub fn strip_glare(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.glare = None;
    s
}

const SHADING_UNITS: &[&str] = &[
    "texture_sampler (normalisation cube)",
    "texture_combiner",
    "specular_lookup",
    "texture_sampler (factor textures)",
];

const GLARE_UNITS: &[&str] = &[
    "glare_condition",
    "chaos_map",
    "gaussian_noise",
    "polygon_variable_generator",
    "polygon_interpolator",
    "bloom_flare_modulator",
    "halo_modulator",
    "glare_combiner",
];

fn shaded_objects() -> Pass {
    Pass {
        step: Step::ShadedObjects,
        name: "objects (shading units, environment reflections)".into(),
        pipeline: "shading + envmap",
        reads: vec![
            "depth buffer".into(),
            "normalisation cube map".into(),
            "factor textures / specular lookup".into(),
            "environment map".into(),
        ],
        writes: vec!["framebuffer".into(), "highlights".into()],
        units: [
            SHADING_UNITS,
            &["reflection_vector", "texture_sampler (environment)"],
        ]
        .concat(),
    }
}

fn shafts_pass(p: &Prepared, sp: ShaftsPass) -> Pass {
    let sub = p.scene.shafts.subplanes > 1;
    let lm = |l: usize| p.light_maps.get(l).is_some_and(|m| m.is_some());
    let s = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    // The camera's object passes go through the clipper when the scene needs it.
    let clip = matches!(sp, ShaftsPass::Depth | ShaftsPass::Objects { .. })
        && crate::scene::clip::clip_needed(&p.scene).is_some();
    let (name, reads, writes, mut units): (String, Vec<String>, Vec<String>, Vec<&'static str>) =
        match sp {
            ShaftsPass::Depth => (
                "depth".into(),
                s(&["objects"]),
                s(&["depth buffer"]),
                vec!["polygon_interpolator", "shadow_compare (depth buffer)"],
            ),
            ShaftsPass::ShadowMap { light } => (
                format!("shadow map, light {light}"),
                s(&["occluders"]),
                vec![format!("shadow map {light}")],
                vec!["polygon_interpolator", "shadow_compare (shadow map)"],
            ),
            ShaftsPass::Objects { light } => {
                let mut r = s(&["depth buffer"]);
                r.push(format!("shadow map {light}"));
                if lm(light) {
                    r.push(format!("light map {light}"));
                }
                (
                    format!("objects (Lambert), light {light}"),
                    r,
                    s(&["framebuffer"]),
                    vec![
                        "polygon_interpolator",
                        "projective_texcoord",
                        "texture_sampler (light map)",
                        "shadow_compare (shadow map)",
                        "shadow_compare (depth buffer)",
                        "modulate",
                        "additive_blend",
                    ],
                )
            }
            ShaftsPass::Planes { light } => {
                let mut r = s(&["depth buffer", "F texture", "h texture"]);
                r.push(format!("shadow map {light}"));
                if lm(light) {
                    r.push(format!("light map {light}"));
                }
                let mut w = s(&["framebuffer"]);
                let mut u = vec![
                    "polygon_interpolator",
                    "texture_sampler (F)",
                    "texture_sampler (h)",
                    "projective_texcoord",
                    "shadow_compare (shadow map)",
                    "shadow_compare (depth buffer)",
                    "modulate",
                    "additive_blend",
                ];
                if sub {
                    r.push("J buffer".into());
                    w.push("J buffer".into());
                    u.push("additive_blend (J buffer)");
                }
                (
                    format!(
                        "sample planes, light {light} (n = {}, m = {})",
                        p.scene.shafts.planes, p.scene.shafts.subplanes
                    ),
                    r,
                    w,
                    u,
                )
            }
        };
    if clip {
        units.insert(0, "clipper");
    }
    Pass {
        step: Step::Shafts(sp),
        name,
        pipeline: "shafts",
        reads,
        writes,
        units,
    }
}

/// The plan as a table.
pub fn plan_table(plan: &Plan) -> String {
    let rows: Vec<Vec<String>> = plan
        .passes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            vec![
                i.to_string(),
                p.name.clone(),
                p.pipeline.to_string(),
                p.reads.join(", "),
                p.writes.join(", "),
            ]
        })
        .collect();
    crate::report::table::text_table(&["#", "pass", "pipeline", "reads", "writes"], &rows)
}
