//! `render --scene` for a scene with an `[environment]` section
//! ([`crate::scene::environment`]): the environment loaded (a built-in map or an `.hdr`
//! file), its voxel map built as `reproduce envmap-*` builds it
//! ([`super::prefilter::env_to_levels`] at the exposure, then the accelerated or the
//! exact prefilter), and the section's thesis object drawn through the units by
//! [`super::render::render_geometry`] from the scene's camera at the scene's image
//! size. A built-in environment scene (`env-<map>-<object>`) gives exactly the image
//! and counters of [`super::render::render_frame`] with the same map (the golden
//! test's path; tests/envmap_scene.rs).

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use rtl_model::error::{check_range, ConfigError};
use rtl_model::Counters;
use serde::Serialize;

use super::image::{ErrorStats, Image};
use super::objects::{object_geometry, LambdaSpec, Object};
use super::prefilter::{build_accelerated_picked, build_exact, env_to_levels, DomePick};
use super::render::{
    render_geometry, render_geometry_against, render_geometry_with_truth, Background, FrameInfo,
    Lookup, RenderOptions, Truth, MAX_IMAGE_SIDE,
};
use super::timing::{predict_frame, FramePrediction};
use super::voxmap::VoxelMap;
use crate::chip::GpuModel;
use crate::reference::envmap_prefilter::{PrefilterParams, Weighting, THESIS_PYRAMID_LEVELS};
use crate::scene::camera::CameraView;
use crate::scene::environment::{
    EnvBackground, EnvDomePick, EnvLambda, EnvLookup, EnvObject, EnvWeighting, EnvironmentSection,
    Prefilter, MAX_SIDE, PYRAMID_DIVISOR,
};
use crate::scene::envmap::EnvMap;
use crate::scene::format::Scene;

// The scene's limits are within the pipeline's (the scene module imports no
// pipeline): the scene's side is bounded by the 3D texture sampler (256), the voxel
// map alone would take 512.
const _: () = assert!(MAX_SIDE <= super::voxmap::MAX_SIDE);
const _: () = assert!(PYRAMID_DIVISOR == 1 << (THESIS_PYRAMID_LEVELS - 1));

/// How the voxel map was built.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MapBuild {
    /// The built-in map's name or the `hdr` path as written.
    pub source: String,
    pub env_width: usize,
    pub env_height: usize,
    /// The exposure of the levels (the section's, or the map's auto exposure).
    pub exposure: f64,
    pub side: u32,
    /// "accelerated, th = …" or "exact".
    pub prefilter: String,
    /// The accelerated build's weight table (None for the exact build).
    pub table_mbytes: Option<f64>,
    pub empty_voxels: Option<u64>,
    /// Voxel map bytes.
    pub map_bytes: u64,
    pub build_seconds: f64,
}

/// The Phong truth of a render and the errors against it (8-bit levels).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneTruth {
    pub truth: Truth,
    /// With the cos φ test (the thesis' Table 5 metric).
    pub cos_phi: ErrorStats,
    /// Without it (what the map stores).
    pub simplified: ErrorStats,
}

/// One rendered environment scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFrame {
    /// The picture, with the object's coverage.
    pub image: Image,
    pub frame: FrameInfo,
    pub counters: BTreeMap<String, Counters>,
    /// [`predict_frame`] on [`GpuModel::geforce3`].
    pub prediction: FramePrediction,
    pub map: MapBuild,
    pub truth: Option<SceneTruth>,
    /// Wall time of the render (geometry to image; truth included when made).
    pub render_seconds: f64,
}

/// The renderer's object.
pub fn object_of(o: EnvObject) -> Object {
    match o {
        EnvObject::Sphere => Object::Sphere,
        EnvObject::Teapot => Object::Teapot,
    }
}

/// The renderer's λ.
pub fn lambda_of(l: EnvLambda) -> LambdaSpec {
    match l {
        EnvLambda::Uniform(x) => LambdaSpec::Uniform(x),
        EnvLambda::NonUniform => LambdaSpec::NonUniform,
    }
}

/// The render options the section asks for (the rest at their defaults: per-vertex
/// λ, the reflection unit).
pub fn render_options(section: &EnvironmentSection) -> RenderOptions {
    RenderOptions {
        exposure: section.exposure,
        background: match section.background {
            EnvBackground::Environment => Background::Environment,
            EnvBackground::Black => Background::Black,
        },
        lookup: match section.lookup {
            EnvLookup::Voxel3d => Lookup::Voxel3D,
            EnvLookup::Auto => Lookup::Auto,
        },
        ..RenderOptions::default()
    }
}

/// The section's voxel map of `env` (loaded from the section): levels at the
/// section's exposure (default: auto), then the section's prefilter at side s with the
/// thesis' parameters — as `reproduce envmap-images` and the golden test build it.
pub fn build_map(
    section: &EnvironmentSection,
    env: &EnvMap,
) -> Result<(VoxelMap, MapBuild), ConfigError> {
    // A process that renders one environment many times (an attribution's or an
    // optimisation's renders of a frame that reflects it) builds each map once: the
    // map is a function of the section and the source map alone, so a copy of the
    // first build is the same bytes. The record keeps the first build's time.
    let key = format!("{section:?}|{}x{}", env.width(), env.height());
    if let Some(hit) = MAP_CACHE
        .lock()
        .ok()
        .and_then(|c| c.iter().find(|(k, _)| *k == key).map(|(_, m)| m.clone()))
    {
        return Ok(hit);
    }
    let built = build_map_uncached(section, env)?;
    if built.0.bytes() <= MAP_CACHE_MAX_BYTES {
        if let Ok(mut c) = MAP_CACHE.lock() {
            if c.len() >= MAP_CACHE_ENTRIES {
                c.remove(0);
            }
            c.push((key, built.clone()));
        }
    }
    Ok(built)
}

/// Maps [`build_map`] keeps: the most recent few, each at most this large (a 128³ map
/// of 16-bit RGB is 12.6 MB; 256³ maps are rebuilt).
const MAP_CACHE_ENTRIES: usize = 4;
const MAP_CACHE_MAX_BYTES: u64 = 16 << 20;

/// (section and source size, the map and its build record), oldest first.
type CachedMap = (String, (VoxelMap, MapBuild));
static MAP_CACHE: std::sync::Mutex<Vec<CachedMap>> = std::sync::Mutex::new(Vec::new());

/// [`build_map`] without the cache: build the map from the source.
fn build_map_uncached(
    section: &EnvironmentSection,
    env: &EnvMap,
) -> Result<(VoxelMap, MapBuild), ConfigError> {
    let exposure = section.exposure_for(env);
    let levels = env_to_levels(env, exposure)?;
    let params = match section.weighting {
        EnvWeighting::SolidAngle => PrefilterParams::thesis(),
        // Eq. (9) as written (`environment.weighting = "uniform"`).
        EnvWeighting::Uniform => {
            let t = PrefilterParams::thesis();
            PrefilterParams::new(t.s(), t.levels(), Weighting::Uniform)?
        }
    };
    let t0 = Instant::now();
    let (map, prefilter, table_mbytes, empty_voxels) = match section.prefilter.resolve(section.side)
    {
        Prefilter::Accelerated { threshold } => {
            let pick = match section.dome_pick {
                EnvDomePick::HalfWeight => DomePick::HalfWeight,
                // The thesis read literally (`environment.dome_pick = "voxel_spacing"`).
                EnvDomePick::VoxelSpacing => DomePick::VoxelSpacing,
            };
            let (map, st) =
                build_accelerated_picked(&levels, section.side, &params, threshold, pick)?;
            (
                map,
                format!("accelerated, th = {threshold}"),
                Some(st.mbytes()),
                Some(st.empty_voxels),
            )
        }
        Prefilter::Exact | Prefilter::Auto => (
            build_exact(&levels, section.side, &params)?,
            "exact".to_string(),
            None,
            None,
        ),
    };
    let source = match (&section.map, &section.hdr) {
        (Some(m), _) => m.clone(),
        (None, Some(h)) => h.written().to_string(),
        (None, None) => String::new(),
    };
    let info = MapBuild {
        source,
        env_width: env.width(),
        env_height: env.height(),
        exposure,
        side: section.side,
        prefilter,
        table_mbytes,
        empty_voxels,
        map_bytes: map.bytes(),
        build_seconds: t0.elapsed().as_secs_f64(),
    };
    Ok((map, info))
}

/// The scene's environment section with its object, after the checks that need the
/// whole scene: no glare (the glare renderer does not draw environments), no shafts
/// lights or objects (this renderer draws only the section's object), an image the
/// renderer can draw. Errors name the field.
fn drawable(scene: &Scene) -> Result<(&EnvironmentSection, EnvObject), ConfigError> {
    let section = scene.environment.as_ref().ok_or_else(|| {
        ConfigError::invalid("environment", "the scene has no [environment] section")
    })?;
    let object = section.object.ok_or_else(|| {
        ConfigError::invalid(
            "environment.object",
            "none given: the environment renderer draws a thesis object (\"sphere\" or \"teapot\")",
        )
    })?;
    if scene.glare.is_some() {
        return Err(ConfigError::invalid(
            "glare",
            "an environment scene with glare is not drawn by the environment renderer",
        ));
    }
    if !scene.objects.is_empty() {
        return Err(ConfigError::invalid(
            "objects",
            &format!(
                "the environment renderer draws only environment.object; remove the scene's {} object(s)",
                scene.objects.len()
            ),
        ));
    }
    if !scene.lights.is_empty() {
        return Err(ConfigError::invalid(
            "lights",
            &format!(
                "the environment renderer has no lights (the environment lights the object); remove the scene's {} light(s)",
                scene.lights.len()
            ),
        ));
    }
    check_range(
        "image.width",
        scene.image.width.into(),
        1,
        MAX_IMAGE_SIDE.into(),
    )?;
    check_range(
        "image.height",
        scene.image.height.into(),
        1,
        MAX_IMAGE_SIDE.into(),
    )?;
    Ok((section, object))
}

/// Render an environment scene (module notes); with `with_truth` also the Phong truth
/// and the errors against it. Every check runs before the map is built.
pub fn render_scene(scene: &Scene, with_truth: bool) -> Result<SceneFrame, ConfigError> {
    render_scene_with(
        scene,
        if with_truth {
            TruthOf::Make
        } else {
            TruthOf::None
        },
    )
}

/// [`render_scene`] with the truth, reusing `truth` from an earlier render of the same
/// scene (`optimize` draws it once per distinct scene: it depends on the map's side
/// through Λ = g(λ·|r|, s, I), never on the voxels). Its object pixels and side must
/// be this render's, else an error naming "envmap_render.truth".
pub fn render_scene_against(scene: &Scene, truth: &Truth) -> Result<SceneFrame, ConfigError> {
    render_scene_with(scene, TruthOf::Reuse(truth))
}

/// What [`render_scene_with`] does about the Phong truth.
enum TruthOf<'a> {
    None,
    Make,
    Reuse(&'a Truth),
}

fn render_scene_with(scene: &Scene, truth_of: TruthOf) -> Result<SceneFrame, ConfigError> {
    let (section, object) = drawable(scene)?;
    scene.validate()?;
    let env = section.load()?;
    let (map, info) = build_map(section, &env)?;
    let t0 = Instant::now();
    let size = (scene.image.width, scene.image.height);
    let cam = CameraView::new(&scene.camera, scene.image);
    let tris = object_geometry(object_of(object), lambda_of(section.lambda), &cam)?;
    let mut opt = render_options(section);
    // The map's exposure (`exposure` or `exposure_rule`) for the background and truth.
    opt.exposure = Some(info.exposure);
    let (image, frame, counters, truth) = match truth_of {
        TruthOf::Make => {
            let (image, truth, stats) =
                render_geometry_with_truth(&env, &map, &tris, &scene.camera, size, &opt)?;
            let t = SceneTruth {
                truth,
                cos_phi: stats.cos_phi,
                simplified: stats.simplified,
            };
            (image, stats.frame, stats.counters, Some(t))
        }
        TruthOf::Reuse(truth) => {
            let (image, stats) =
                render_geometry_against(&env, &map, &tris, &scene.camera, size, &opt, truth)?;
            let t = SceneTruth {
                truth: truth.clone(),
                cos_phi: stats.cos_phi,
                simplified: stats.simplified,
            };
            (image, stats.frame, stats.counters, Some(t))
        }
        TruthOf::None => {
            let (image, frame, counters) =
                render_geometry(&env, &map, &tris, &scene.camera, size, &opt)?;
            (image, frame, counters, None)
        }
    };
    let render_seconds = t0.elapsed().as_secs_f64();
    Ok(SceneFrame {
        prediction: predict_frame(&GpuModel::geforce3(), &frame),
        image,
        frame,
        counters,
        map: info,
        truth,
        render_seconds,
    })
}

/// Write `img` as a PNG, creating its directory; errors name `out` and the path.
fn write_png(img: &Image, path: &Path) -> Result<(), String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("out: {}: {e}", dir.display()))?;
    }
    img.write_png(path)
        .map_err(|e| format!("out: {}: {e}", path.display()))
}

/// `render --scene` for an environment scene: render it and write the PNG at `out`;
/// with `reference`, the Phong truth (with the cos φ test) written there. The
/// caller reports it: [`print_text`], or `render --json`'s object
/// (`report::render_json`, built in `frame::cli`).
pub fn render_and_write(
    scene: &Scene,
    out: &Path,
    reference: Option<&Path>,
) -> Result<SceneFrame, String> {
    let f = render_scene(scene, reference.is_some()).map_err(|e| e.to_string())?;
    write_png(&f.image, out)?;
    if let (Some(path), Some(t)) = (reference, &f.truth) {
        write_png(&t.truth.cos_phi, path).map_err(|e| e.replacen("out:", "reference:", 1))?;
    }
    Ok(f)
}

/// The text report of [`render_and_write`]'s frame: the counters, the elaboration,
/// the predicted GeForce3 time, and with `reference` the errors against both truths.
pub fn print_text(
    scene: &Scene,
    f: &SceneFrame,
    out: &Path,
    reference: Option<&Path>,
) -> Result<(), String> {
    let el = &f.frame.elaboration;
    let m = &f.map;
    println!(
        "{} ({}x{}): wrote {} in {:.2} s of simulation",
        scene.name,
        f.frame.width,
        f.frame.height,
        out.display(),
        f.render_seconds
    );
    println!(
        "map: {} ({} × {}, exposure {:.4}), {}³ voxels, {}, {:.1} s{}",
        m.source,
        m.env_width,
        m.env_height,
        m.exposure,
        m.side,
        m.prefilter,
        m.build_seconds,
        m.table_mbytes
            .map_or(String::new(), |mb| format!(", table {mb:.1} MB"))
    );
    println!(
        "{} triangles, {} fragments, {} object pixels, {} background pixels",
        f.frame.triangles, f.frame.fragments, f.frame.shaded, f.frame.background_pixels
    );
    print!("{}", crate::report::table::counters_table(&f.counters));
    println!(
        "\nelaboration ({} lookup; texture {} bytes, {} saved):",
        if el.slice_2d {
            "2D cube-map slice"
        } else {
            "3D voxel map"
        },
        el.texture_bytes,
        el.texture_bytes_saved
    );
    print!("{}", crate::report::table::elaboration_table(&el.units));
    let p = &f.prediction;
    println!(
        "\npredicted GeForce3 time: {:.4} ms (clear {:.4} ms, object {:.4} ms ({} bound), background {:.4} ms; {:.2} MB moved)",
        p.seconds * 1e3,
        p.clear_seconds * 1e3,
        p.object_seconds * 1e3,
        if p.object_memory_bound() { "memory" } else { "fill" },
        p.background_seconds * 1e3,
        p.bytes / 1e6
    );
    if let (Some(path), Some(t)) = (reference, &f.truth) {
        for (what, s) in [
            ("with the cos φ test", &t.cos_phi),
            ("without it", &t.simplified),
        ] {
            println!(
                "error against the Phong truth {what} ({} object pixels), 8-bit levels: mean |Δ| R {:.3} G {:.3} B {:.3}, max R {:.0} G {:.0} B {:.0}",
                s.pixels, s.mean[0], s.mean[1], s.mean[2], s.max[0], s.max[1], s.max[2]
            );
        }
        println!("Phong truth (with the cos φ test): {}", path.display());
    }
    Ok(())
}
