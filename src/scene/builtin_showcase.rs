//! The showcase built-in, `night-street`: one frame through every pipeline. A wet
//! street under two street lamps in light fog: the lamps' cones are light shafts
//! (sample planes), the walls and poles are Lambert objects with shadow maps, the
//! street (wet: Blinn–Phong), a plaster wall (Oren–Nayar) and a chrome ball
//! (Cook–Torrance metal) are shaded by the shading units, and the glare pass gives
//! the lamps bloom and halo and turns the chrome's highlight, found by the shading
//! units, into a glare source when Table 2's rule passes.

use super::builtin_glare::source;
use super::environment::{EnvironmentSection, Reflector};
use super::format::{
    Camera, FScale, ImageSize, Light, LightKind, LightMap, Medium, Object, Scene, ShaftsConfig,
    Shape,
};
use super::glare::{
    Background, Determinants, GlareHw, GlareModel, GlareSection, ShadedHighlights, SourceKind,
};
use super::material::{Distribution, FresnelKind, Material};
use rtl_model::chip_preset::ChipPreset;

/// Names of the showcase built-ins.
pub const SHOWCASE_NAMES: &[&str] = &["night-street"];

/// A showcase built-in by name.
pub fn showcase_builtin(name: &str) -> Option<Scene> {
    match name {
        "night-street" => Some(night_street()),
        _ => None,
    }
}

/// Lamp heads (world positions of the glowing covers).
const LAMPS: [[f64; 3]; 2] = [[-2.8, 4.6, -6.0], [3.9, 4.6, -15.0]];
/// Warm sodium-white lamp colour.
const LAMP_COLOR: [f64; 3] = [1.0, 0.88, 0.65];

fn lamp_light(head: [f64; 3]) -> Light {
    Light {
        kind: LightKind::Spot,
        position: [head[0], head[1] - 0.2, head[2]],
        direction: [0.0, -1.0, 0.0],
        cutoff_deg: 38.0,
        intensity: 40.0,
        color: LAMP_COLOR,
        light_map: Some(LightMap::Smooth { exponent: 1.0 }),
    }
}

fn lambert_box(min: [f64; 3], max: [f64; 3], color: [f64; 3], occluder: bool) -> Object {
    Object {
        shape: Shape::Box { min, max },
        color,
        occluder,
        material: None,
    }
}

/// The pole (beside the head, towards the kerb) and the arm over the street. Neither
/// casts shadows: seen from the other lamp, a pole's faces lie almost level with the
/// light and project far beyond its shadow map, whose pass walks each triangle's whole
/// bounding box (docs/frame.md); the chrome ball is the scene's occluder.
fn lamp_post(head: [f64; 3], side: f64) -> [Object; 2] {
    let px = head[0] + side * 0.9;
    let grey = [0.18, 0.18, 0.19];
    [
        lambert_box(
            [px - 0.08, 0.0, head[2] - 0.08],
            [px + 0.08, head[1] + 0.15, head[2] + 0.08],
            grey,
            false,
        ),
        lambert_box(
            [px.min(head[0]) - 0.05, head[1] + 0.1, head[2] - 0.05],
            [px.max(head[0]) + 0.05, head[1] + 0.2, head[2] + 0.05],
            grey,
            false,
        ),
    ]
}

/// The showcase scene (module notes). 720 × 480.
pub fn night_street() -> Scene {
    let objects = street_objects();
    let glare = lamp_glare();
    Scene {
        chip: ChipPreset::GeForce2,
        name: "night-street: a wet street under two lamps in light fog (every pipeline)".into(),
        seed: 21,
        image: ImageSize::default(),
        camera: Camera {
            eye: [0.0, 1.7, 5.0],
            look_at: [0.2, 1.6, -10.0],
            up: [0.0, 1.0, 0.0],
            fovy_deg: 42.0,
            near: 0.5,
            far: 100.0,
        },
        medium: Medium {
            rho: 0.03,
            kappa: 0.8,
            k: 1.0,
        },
        lights: LAMPS.iter().map(|&h| lamp_light(h)).collect(),
        objects,
        // The F table spans the scattering angles the cones actually meet (seen from
        // the side, the paper's table has 26 codes there: docs/shafts.md).
        shafts: ShaftsConfig {
            f_scale: FScale::LitVolume,
            ..ShaftsConfig::default()
        },
        glare: Some(glare),
        // The street's surroundings as the chrome ball reflects them: Venice at dusk
        // (a Poly Haven CC0 map shipped in src/scene/data/envmaps/), dimmed to night.
        rounding: None,
        shading_hw: None,
        shading_sphere: None,
        test_scene: None,
        environment: Some(EnvironmentSection {
            map: Some("venice_sunset".into()),
            exposure: Some(NIGHT_EXPOSURE),
            side: 64,
            reflectors: vec![Reflector {
                object: CHROME,
                lambda: 0.9,
                reflectance: 0.6,
            }],
            ..EnvironmentSection::default()
        }),
    }
}

/// The street's objects, in `objects`' order ([`CHROME`] is index 1): the wet street,
/// the chrome ball, the plaster and brick walls, and the two lamp posts.
fn street_objects() -> Vec<Object> {
    let street = Object {
        shape: Shape::Plane {
            center: [0.0, 0.0, -13.0],
            normal: [0.0, 1.0, 0.0],
            tangent: [1.0, 0.0, 0.0],
            half_size: [5.5, 15.0],
        },
        color: [0.1, 0.1, 0.11],
        occluder: false,
        // Wet asphalt: a dark diffuse base under a sharp water film.
        material: Some(Material::BlinnPhong {
            ks: 0.5,
            exponent: 12.0,
            normalized: false,
        }),
    };
    let chrome = Object {
        shape: Shape::Sphere {
            center: [-1.4, 0.55, -4.2],
            radius: 0.55,
        },
        color: [0.05, 0.05, 0.05],
        occluder: true,
        // Chrome: η ≈ 3.2 + 3.3i, polished.
        material: Some(Material::CookTorrance {
            distribution: Distribution::Beckmann,
            roughness: 0.12,
            ior: 3.2,
            extinction: 3.3,
            fresnel: FresnelKind::Exact,
        }),
    };
    let plaster = Object {
        shape: Shape::Box {
            min: [5.5, 0.0, -28.0],
            max: [6.5, 9.0, -1.0],
        },
        color: [0.6, 0.55, 0.48],
        occluder: false,
        material: Some(Material::OrenNayar { sigma_deg: 30.0 }),
    };
    // The walls stand beside the cones, never between a lamp and what it lights: they
    // cast no shadow worth a shadow-map pass over their large faces.
    let brick = lambert_box(
        [-6.5, 0.0, -28.0],
        [-5.5, 9.0, -1.0],
        [0.42, 0.27, 0.2],
        false,
    );
    let mut objects = vec![street, chrome, plaster, brick];
    objects.extend(lamp_post(LAMPS[0], -1.0));
    objects.extend(lamp_post(LAMPS[1], 1.0));
    objects
}

/// The glare section: the two lamps as circular sources without flare, the chrome
/// ball's shaded highlight of the first, in a light mist.
fn lamp_glare() -> GlareSection {
    let sources = LAMPS
        .iter()
        .map(|&head| {
            let mut s = source(SourceKind::Circle, head, 1500.0);
            s.a = 0.15;
            s.flare = false;
            s.color = LAMP_COLOR;
            s
        })
        .collect();
    let mut glare = GlareSection {
        background: Background::Shafts,
        determinants: Determinants::default(),
        sources,
        highlights: vec![],
        shaded_highlights: Some(ShadedHighlights {
            light: 0,
            intensity: 600.0,
            radius: 0.03,
        }),
        model: GlareModel::default(),
        hw: GlareHw::default(),
        frame: 0,
    };
    glare.determinants.mist = 0.2;
    glare.model.bloom_k = 0.3;
    glare.model.halo_k = 0.08;
    glare
}

/// `objects[CHROME]` is the chrome ball.
const CHROME: usize = 1;
/// Exposure of the dusk map for a night scene.
const NIGHT_EXPOSURE: f64 = 0.5;
