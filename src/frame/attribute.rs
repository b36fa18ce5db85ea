//! `attribute` on a frame scene (`frame::sweep::is_frame_scene`: `night-street`,
//! `shaded-metal`, `street-light`, …): every pass's error sources on the frame's error.
//!
//! The sources are each pipeline's own (`pipeline::shafts::attribute`,
//! `pipeline::glare::attribute`, `pipeline::envmap::attribute`, and the shading
//! units' `[shading_hw]` widths from `pipeline::shading::attribute::scene_sources`),
//! for every pipeline the frame runs, each named with its pipeline
//! (`shafts: texel_bits`). Each render goes through the frame as `render` renders it
//! and is compared with the frame's composed f64 reference
//! (`reproduce::frame_error_and_reference`): so a source's share is of the whole
//! picture's squared error, whichever pass it sits in.
//!
//! "All ideal" is held to the sum of the pipelines' own bounds (the frame's error is
//! at most the sum of its passes' errors, `reproduce`'s module notes).

use super::plan::frame_pipelines;
use super::reproduce::frame_error_and_reference;
use super::run::render;
use crate::pipeline::{envmap, glare, shading, shafts};
use crate::report::attribution::{attribute, Attribution, Bound, Source};
use crate::scene::format::Scene;
use std::path::Path;

/// The path `attribute` takes, by what the scene holds (never by its name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AttributePath {
    /// The foundation test scene: no error sources (refused).
    TestScene,
    /// A shading sphere's widths (`pipeline::shading::attribute`).
    Shading,
    /// A scene of several pipelines, through the frame.
    Frame,
    /// A glare scene (over its shafts backdrop, if any).
    Glare,
    /// An environment-map scene's thesis object.
    Environment,
    /// No lights, glare or environment object: nothing to attribute (refused).
    Nothing,
    /// A shafts scene.
    Shafts,
}

/// [`AttributePath`] of a loaded scene.
pub fn attribute_path(s: &Scene) -> Result<AttributePath, String> {
    use crate::scene::format::SceneKind;
    Ok(match s.kind() {
        SceneKind::Test => AttributePath::TestScene,
        SceneKind::ShadingSphere(_) => AttributePath::Shading,
        SceneKind::Frame if super::sweep::is_frame_scene(s)? => AttributePath::Frame,
        SceneKind::Frame if s.glare.is_some() => AttributePath::Glare,
        SceneKind::Frame if s.environment.as_ref().is_some_and(|e| e.object.is_some()) => {
            AttributePath::Environment
        }
        SceneKind::Frame if s.lights.is_empty() => AttributePath::Nothing,
        SceneKind::Frame => AttributePath::Shafts,
    })
}

/// Every source of the frame's pipelines, each named with its pipeline.
pub fn sources(base: &Scene) -> Result<Vec<Source<Scene>>, String> {
    let mut v = Vec::new();
    for p in frame_pipelines(base).map_err(|e| e.to_string())? {
        let of_pipeline = match p {
            "shafts" => shafts::attribute::sources(base),
            "shading" => shading::attribute::scene_sources(base),
            "environment" => envmap::attribute::sources(base),
            "glare" => glare::attribute::sources(base),
            _ => Vec::new(),
        };
        v.extend(of_pipeline.into_iter().map(|s| Source {
            name: format!("{p}: {}", s.name),
            ..s
        }));
    }
    Ok(v)
}

/// The frame's bound: the sum of its pipelines' bounds (module notes).
pub fn bound(base: &Scene) -> Result<Bound, String> {
    let bounds: Vec<(&str, Bound)> = frame_pipelines(base)
        .map_err(|e| e.to_string())?
        .into_iter()
        .filter_map(|p| match p {
            "shafts" => Some((p, shafts::attribute::bound())),
            "shading" => Some((p, shading::attribute::bound())),
            "environment" => Some((p, envmap::attribute::bound())),
            "glare" => Some((p, glare::attribute::bound())),
            _ => None,
        })
        .collect();
    Ok(Bound {
        mean_abs: bounds.iter().map(|(_, b)| b.mean_abs).sum(),
        outlier_fraction: bounds.iter().map(|(_, b)| b.outlier_fraction).sum(),
        outlier_levels: bounds
            .iter()
            .map(|(_, b)| b.outlier_levels)
            .fold(0.0, f64::max),
        why: format!(
            "the sum of the passes' bounds ({})",
            bounds
                .iter()
                .map(|(p, b)| format!("{p}: mean |Δ| ≤ {}", b.mean_abs))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    })
}

/// Attribute the frame's error of `scene` into `out` (module notes).
pub fn attribute_frame(scene: &Scene, out: &Path) -> Result<Attribution, String> {
    let (w, h) = (scene.image.width, scene.image.height);
    attribute(
        scene.short_name().trim(),
        scene,
        (w, h),
        &sources(scene)?,
        &bound(scene)?,
        |s| s.validate().map_err(|e| e.to_string()),
        |s| {
            let f = render(s).map_err(|e| e.to_string())?;
            let (_, reference) = frame_error_and_reference(s, &f)?;
            Ok((f.fb.levels(), reference))
        },
        out,
    )
}
