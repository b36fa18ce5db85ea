//! Built-in scenes: the paper's test scenes (Dobashi et al.), 720 × 480.
//!
//! # Brightness
//!
//! The shafts term is I_s = ∫ H·I_l·g dt with g = ρ·F(α)·exp(−ρκ(s + t))/s² and
//! I_l = intensity × colour × light map; 1.0 is full scale of the 8-bit framebuffer.
//! Across a spot's cone seen from the side (α ≈ 90°, F ≈ 1.035·K) at distance s from
//! the light, a chord of length w ≈ 2·s·tan(cutoff) gives
//! I_s ≈ I·ρ·K·(⅔·w)/s²·exp(−ρκ(s + t)) for a smooth (1 − r²) map, i.e. ∝ 1/s: the cone
//! is brightest next to the light. Every light is therefore hung just above the top
//! of the frame, and the brightest visible path integral (about 1.3–2 units below the
//! light) is tuned to ~0.3–0.6 of full scale, so the shafts are clearly visible and
//! the 8-bit sum of 30 planes neither saturates nor sinks into the rounding noise
//! (`tests/scene.rs` ray-marches every builtin and checks the bright end lies in that
//! band).
//!
//! The medium is thin (ρκ = 0.02 per unit, exp(−ρκ·20) ≈ 0.67 over a typical
//! eye–light–point path) so distance dims the shafts only mildly; ρ·K sets the
//! scattering (ρK = 0.025), and the intensities (50–120) are then what puts the shafts
//! in the band above. With them a Lambertian floor ~9.5–11 units below a light
//! receives I·albedo/d² ≈ 0.3–0.5 and the tops of the objects stay at or below ~1 —
//! the objects stay visible beside the shafts, and both share the framebuffer's range.

use rtl_model::chip_preset::ChipPreset;
use rtl_model::error::ConfigError;

use super::format::{
    Camera, ImageSize, Light, LightKind, LightMap, Medium, Object, Scene, ShaftsConfig, Shape,
};

/// Names accepted by [`builtin`].
pub const BUILTIN_NAMES: &[&str] = &["fig4", "fig6", "stage"];

/// A built-in scene by name (see [`BUILTIN_NAMES`]); an unknown name is an error
/// naming `scene`. Every built-in validates.
pub fn builtin(name: &str) -> Result<Scene, ConfigError> {
    let scene = match name {
        "fig4" => fig4(),
        "fig6" => fig6(),
        "stage" => stage(),
        other => match super::builtin_glare::glare_builtin(other)
            .or_else(|| super::builtin_showcase::showcase_builtin(other))
            .or_else(|| super::builtin_environment::environment_builtin(other))
        {
            Some(s) => s,
            None => {
                return Err(ConfigError::invalid(
                    "scene",
                    &format!(
                        "unknown built-in scene `{name}` (known: {})",
                        BUILTIN_NAMES
                            .iter()
                            .chain(super::builtin_glare::GLARE_BUILTIN_NAMES)
                            .chain(super::builtin_showcase::SHOWCASE_NAMES)
                            .chain(super::builtin_environment::ENVIRONMENT_BUILTIN_NAMES)
                            .cloned()
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ))
            }
        },
    };
    scene.validate()?;
    Ok(scene)
}

/// The TOML text of a built-in scene, to start a scene file from: compact and
/// commented ([`super::print::scene_toml`]), and
/// `Scene::from_toml_str(&builtin_toml(x)?)? == builtin(x)?`.
pub fn builtin_toml(name: &str) -> Result<String, ConfigError> {
    let scene = builtin(name)?;
    let header = format!(
        "# Built-in scene `{name}` of glare-pipeline ({}).\n\
         # Render it with `glare-pipeline render --scene FILE`; every field is in docs/scenes.md.\n\n",
        scene.name
    );
    super::print::scene_toml(&scene, &header)
}

/// The medium of every built-in: ρ = 0.025, κ = 0.8 (ρκ = 0.02), K = 1 (see the module
/// documentation for the reasoning).
fn medium() -> Medium {
    Medium {
        rho: 0.025,
        kappa: 0.8,
        k: 1.0,
    }
}

fn camera(eye: [f64; 3], look_at: [f64; 3]) -> Camera {
    Camera {
        eye,
        look_at,
        up: [0.0, 1.0, 0.0],
        fovy_deg: 40.0,
        near: 0.5,
        far: 40.0,
    }
}

fn spot(position: [f64; 3], target: [f64; 3], cutoff_deg: f64, intensity: f64) -> Light {
    Light {
        kind: LightKind::Spot,
        position,
        direction: [
            target[0] - position[0],
            target[1] - position[1],
            target[2] - position[2],
        ],
        cutoff_deg,
        intensity,
        color: [1.0, 1.0, 1.0],
        light_map: Some(LightMap::Smooth { exponent: 1.0 }),
    }
}

fn floor(half_size: [f64; 2], color: [f64; 3]) -> Object {
    Object {
        shape: Shape::Plane {
            center: [0.0, 0.0, 0.0],
            normal: [0.0, 1.0, 0.0],
            tangent: [1.0, 0.0, 0.0],
            half_size,
        },
        color,
        // A receiver only: nothing in the air lies below it.
        occluder: false,
        material: None,
    }
}

/// The paper's Fig. 4 test: one spotlight in an empty dark room, n swept (10 … 200).
/// The light hangs above the top of the frame, left of centre, pointing down and to
/// the right (and slightly towards the camera); the camera looks horizontally across
/// the cone, which is seen from the side. No objects, so no occluders (no shadow-map
/// unit) and H = 1; m = 1 (no sub-planes), as in the figure.
///
/// Unlike the other built-ins this one is bright: the beam is a theatre spot, flat with
/// a hard edge ("the light distribution often changes abruptly", the paper's §4.3), at 3× the others' intensity, so the beam's bulk sits at 20–80 levels and
/// saturates next to the light, as in the paper's pictures. Fig. 4 weighs the
/// sampling error of few planes (which grows with the beam's brightness and the
/// sharpness of its edge) against the 8-bit rounding of many planes (about half a level
/// per plane, whatever the brightness); in a dim beam the rounding wins at every n.
pub fn fig4() -> Scene {
    Scene {
        chip: ChipPreset::GeForce2,
        name: "fig4: one spotlight in an empty dark room (Dobashi et al. Fig. 4)".into(),
        seed: 4,
        image: ImageSize::default(),
        camera: camera([0.0, 3.0, 14.0], [0.0, 3.0, 0.0]),
        medium: medium(),
        lights: vec![{
            // A theatre spot: flat across the beam, hard edge ((1 − r²)⁰ = 1 inside).
            let mut l = spot([-3.0, 10.0, 0.0], [1.0, 0.0, 1.0], 20.0, 180.0);
            l.light_map = Some(LightMap::Smooth { exponent: 0.0 });
            l
        }],
        objects: vec![],
        shafts: ShaftsConfig {
            subplanes: 1,
            ..ShaftsConfig::default()
        },
        glare: None,
        rounding: None,
        shading_hw: None,
        shading_sphere: None,
        test_scene: None,
        environment: None,
    }
}

/// The paper's Fig. 6 (and Fig. 5's scene): a sphere lit from straight above by one
/// spotlight; the sphere's shadow cuts a dark core into the cone below it, seen from
/// the side; a floor plane under it receives the light (and the sphere's shadow).
/// A bright theatre spot like fig4's (its beam saturates next to the light); n = 30,
/// m = 6.
pub fn fig6() -> Scene {
    Scene {
        chip: ChipPreset::GeForce2,
        name: "fig6: a sphere's shadow in a spotlight's cone (Dobashi et al. Fig. 6)".into(),
        seed: 6,
        image: ImageSize::default(),
        camera: camera([0.0, 3.0, 13.0], [0.0, 3.0, 0.0]),
        medium: medium(),
        lights: vec![{
            // The theatre spot of fig4 (flat beam, hard edge), as bright: its edge and
            // the sphere's shadow are what the sub-planes anti-alias.
            let mut l = spot([0.0, 9.5, 0.0], [0.0, 0.0, 0.0], 25.0, 150.0);
            l.light_map = Some(LightMap::Smooth { exponent: 0.0 });
            l
        }],
        objects: vec![
            Object {
                shape: Shape::Sphere {
                    center: [0.0, 3.5, 0.0],
                    radius: 1.0,
                },
                // Its top is 5 units below the light: 150·0.15/25 ≈ 0.9 of full scale.
                color: [0.15, 0.15, 0.17],
                occluder: true,
                material: None,
            },
            // 9.5 units below the light: 150·0.35/90 ≈ 0.6 of full scale.
            floor([10.0, 10.0], [0.35, 0.35, 0.35]),
        ],
        shafts: ShaftsConfig::default(),
        glare: None,
        rounding: None,
        shading_hw: None,
        shading_sphere: None,
        test_scene: None,
        environment: None,
    }
}

/// The paper's Fig. 7: a stage under 5 spotlights hung above it (just above the
/// frame), pointing down at different angles, two of them through polka-dot light
/// maps; on the stage floor a teapot, a box and a sphere; a back wall behind. Light
/// colours are tinted, as stage lights are. n = 30, m = 6.
pub fn stage() -> Scene {
    let tinted = |mut l: Light, color: [f64; 3], map: LightMap| {
        l.color = color;
        l.light_map = Some(map);
        l
    };
    Scene {
        chip: ChipPreset::GeForce2,
        name: "stage: five spotlights over a stage (Dobashi et al. Fig. 7)".into(),
        seed: 7,
        image: ImageSize::default(),
        camera: camera([0.0, 3.5, 17.0], [0.0, 3.5, 0.0]),
        medium: medium(),
        lights: vec![
            tinted(
                spot([-7.0, 11.0, 1.5], [-5.0, 0.0, 1.0], 18.0, 80.0),
                [1.0, 0.85, 0.6],
                LightMap::Smooth { exponent: 1.0 },
            ),
            tinted(
                spot([-3.5, 11.0, 2.0], [-3.5, 0.0, 0.5], 18.0, 80.0),
                [1.0, 1.0, 1.0],
                LightMap::PolkaDots {
                    dots: 5,
                    radius: 0.3,
                },
            ),
            tinted(
                spot([0.0, 11.0, 2.5], [0.0, 0.0, 1.5], 16.0, 120.0),
                [0.7, 0.85, 1.0],
                LightMap::Smooth { exponent: 2.0 },
            ),
            tinted(
                spot([3.5, 11.0, 2.0], [3.0, 0.0, -0.2], 18.0, 80.0),
                [1.0, 0.75, 0.75],
                LightMap::PolkaDots {
                    dots: 4,
                    radius: 0.35,
                },
            ),
            tinted(
                spot([7.0, 11.0, 1.5], [5.5, 0.0, 1.0], 18.0, 80.0),
                [0.8, 1.0, 0.8],
                LightMap::Smooth { exponent: 1.0 },
            ),
        ],
        objects: vec![
            Object {
                shape: Shape::Teapot {
                    position: [-3.5, 0.0, 0.5],
                    scale: 0.7,
                    rotate_y_deg: 30.0,
                    subdivisions: 8,
                },
                color: [0.75, 0.7, 0.6],
                occluder: true,
                material: None,
            },
            Object {
                shape: Shape::Box {
                    min: [2.2, 0.0, -1.0],
                    max: [3.8, 1.6, 0.6],
                },
                color: [0.5, 0.55, 0.7],
                occluder: true,
                material: None,
            },
            Object {
                shape: Shape::Sphere {
                    center: [0.0, 0.9, 1.5],
                    radius: 0.9,
                },
                color: [0.7, 0.4, 0.35],
                occluder: true,
                material: None,
            },
            // The stage floor and the back wall: receivers only.
            floor([9.0, 5.0], [0.55, 0.45, 0.35]),
            Object {
                shape: Shape::Plane {
                    center: [0.0, 5.0, -5.0],
                    normal: [0.0, 0.0, 1.0],
                    tangent: [1.0, 0.0, 0.0],
                    half_size: [9.0, 5.0],
                },
                color: [0.35, 0.35, 0.45],
                occluder: false,
                material: None,
            },
        ],
        shafts: ShaftsConfig::default(),
        glare: None,
        rounding: None,
        shading_hw: None,
        shading_sphere: None,
        test_scene: None,
        environment: None,
    }
}
