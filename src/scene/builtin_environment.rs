//! Built-in environment-map scenes (Okumura's thesis §4.3): every built-in
//! map × the sphere and the teapot, named `env-<map>-<object>`, rendered as
//! `reproduce envmap-images` and the golden test render them: the thesis camera,
//! 256 × 256, the accelerated 128³ map (th = 0.001) at the map's auto exposure, the
//! sphere at uniform λ = 0.5 and the teapot at the thesis' non-uniform λ, the 3D
//! lookup, the environment behind.

use super::environment::{
    thesis_camera, EnvLambda, EnvObject, EnvironmentSection, Prefilter, DEFAULT_SIDE,
    THESIS_THRESHOLD,
};
use super::envmap::BUILTIN_NAMES as MAP_NAMES;
use super::format::{ImageSize, Medium, Scene, ShaftsConfig};
use rtl_model::chip_preset::ChipPreset;

/// Names of the built-in environment scenes (`env-<map>-<object>`).
pub const ENVIRONMENT_BUILTIN_NAMES: &[&str] = &[
    "env-pattern-sphere",
    "env-pattern-teapot",
    "env-venice_sunset-sphere",
    "env-venice_sunset-teapot",
    "env-st_fagans_interior-sphere",
    "env-st_fagans_interior-teapot",
];

/// Image side of the built-ins (`reproduce envmap-images`' default).
pub const ENVIRONMENT_IMAGE_SIDE: u32 = 256;

/// The objects of the built-ins, with their λ (the golden test's settings).
const OBJECTS: [(EnvObject, EnvLambda); 2] = [
    (EnvObject::Sphere, EnvLambda::Uniform(0.5)),
    (EnvObject::Teapot, EnvLambda::NonUniform),
];

/// The built-in environment scene `name` (see [`ENVIRONMENT_BUILTIN_NAMES`]), or None.
pub fn environment_builtin(name: &str) -> Option<Scene> {
    let rest = name.strip_prefix("env-")?;
    let (map, object) = rest.rsplit_once('-')?;
    let map = *MAP_NAMES.iter().find(|m| **m == map)?;
    let (object, lambda) = *OBJECTS.iter().find(|(o, _)| o.name() == object)?;
    Some(environment_scene(map, object, lambda))
}

fn environment_scene(map: &str, object: EnvObject, lambda: EnvLambda) -> Scene {
    let shown_lambda = match lambda {
        EnvLambda::Uniform(l) => format!("λ = {l}"),
        EnvLambda::NonUniform => "non-uniform λ".to_string(),
    };
    Scene {
        chip: ChipPreset::GeForce2,
        name: format!(
            "env-{map}-{}: the thesis' {} ({shown_lambda}) in the {map} environment \
             (Okumura §4.3, multi-scale environment map)",
            object.name(),
            object.name()
        ),
        seed: 1,
        image: ImageSize {
            width: ENVIRONMENT_IMAGE_SIDE,
            height: ENVIRONMENT_IMAGE_SIDE,
        },
        camera: thesis_camera(),
        medium: Medium::default(),
        lights: vec![],
        objects: vec![],
        shafts: ShaftsConfig::default(),
        glare: None,
        rounding: None,
        shading_hw: None,
        shading_sphere: None,
        test_scene: None,
        environment: Some(EnvironmentSection {
            map: Some(map.to_string()),
            object: Some(object),
            lambda,
            side: DEFAULT_SIDE,
            prefilter: Prefilter::Accelerated {
                threshold: THESIS_THRESHOLD,
            },
            ..EnvironmentSection::default()
        }),
    }
}
