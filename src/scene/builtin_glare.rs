//! Built-in glare scenes (Matsuda and Ikedo, the paper's Figs. 4, 5, 7, 8), 720 × 480.
//!
//! The camera's 25° field of view puts ~19 pixels on a degree, so the halo's 3°
//! ring is ~57 pixels across and its 0.35° width ~7 pixels, and the bloom's tail
//! (down to half a level at ~20°) fills most of the frame around a bright source.

use super::format::{
    Camera, ImageSize, Light, LightKind, LightMap, Medium, Object, Scene, ShaftsConfig, Shape,
};
use super::glare::{
    Background, Determinants, Fluctuation, GlareHw, GlareModel, GlareSection, GlareSource,
    SourceKind,
};
use rtl_model::chip_preset::ChipPreset;

/// Names of the built-in glare scenes.
pub const GLARE_BUILTIN_NAMES: &[&str] = &[
    "glare-point",
    "glare-elliptic",
    "glare-flare",
    "street-light",
    "leaves",
    "shaded-metal",
    "shaded-dielectric",
];

fn camera(eye: [f64; 3], look_at: [f64; 3]) -> Camera {
    Camera {
        eye,
        look_at,
        up: [0.0, 1.0, 0.0],
        fovy_deg: 25.0,
        near: 0.5,
        far: 100.0,
    }
}

fn night() -> Background {
    Background::Sky {
        top: [0.004, 0.006, 0.02],
        bottom: [0.02, 0.02, 0.035],
    }
}

/// A source with every glare component on and no directivity.
pub fn source(kind: SourceKind, position: [f64; 3], intensity: f64) -> GlareSource {
    GlareSource {
        kind,
        position,
        a: 0.0,
        b: 0.0,
        n: [0.0, 1.0, 0.0],
        vertices: vec![],
        intensity,
        area_size: 1.0,
        directivity: None,
        color: [1.0, 0.95, 0.85],
        bloom: true,
        halo: true,
        flare: true,
        fluctuation: None,
    }
}

fn glare_scene(name: &str, seed: u64, camera: Camera, glare: GlareSection) -> Scene {
    Scene {
        chip: ChipPreset::GeForce2,
        name: name.into(),
        seed,
        image: ImageSize::default(),
        camera,
        medium: Medium::default(),
        lights: vec![],
        objects: vec![],
        shafts: ShaftsConfig::default(),
        glare: Some(glare),
        rounding: None,
        shading_hw: None,
        shading_sphere: None,
        test_scene: None,
        environment: None,
    }
}

fn section(background: Background, sources: Vec<GlareSource>) -> GlareSection {
    GlareSection {
        background,
        determinants: Determinants::default(),
        sources,
        highlights: vec![],
        shaded_highlights: None,
        model: GlareModel::default(),
        hw: GlareHw::default(),
        frame: 0,
    }
}

/// Fig. 4 (left): a point source with bloom (eq. 1), nothing else.
pub fn glare_point() -> Scene {
    let mut s = source(SourceKind::Point, [0.0, 0.0, -20.0], 2000.0);
    s.halo = false;
    s.flare = false;
    glare_scene(
        "glare-point: a point source with bloom (Matsuda-Ikedo Fig. 4, left)",
        4,
        camera([0.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        section(night(), vec![s]),
    )
}

/// Fig. 4 (right): an elliptic source (a lamp cover, 3:1, tilted 30°) with bloom (eq. 4).
pub fn glare_elliptic() -> Scene {
    let mut s = source(SourceKind::Elliptic, [0.0, 0.0, -20.0], 2000.0);
    s.a = 0.3;
    s.b = 0.1;
    s.n = [-0.5, 0.866, 0.0];
    s.halo = false;
    s.flare = false;
    glare_scene(
        "glare-elliptic: an elliptic source with bloom (Matsuda-Ikedo Fig. 4, right)",
        4,
        camera([0.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        section(night(), vec![s]),
    )
}

/// Fig. 5: flare lines from an elliptic source, seen by a near-sighted viewer with
/// glasses (flare +), with its bloom.
pub fn glare_flare() -> Scene {
    let mut s = source(SourceKind::Elliptic, [0.0, 0.0, -20.0], 3000.0);
    s.a = 0.25;
    s.b = 0.1;
    s.n = [0.0, 1.0, 0.0];
    s.halo = false;
    let mut g = section(night(), vec![s]);
    g.determinants.glasses = true;
    glare_scene(
        "glare-flare: flare lines from an elliptic source (Matsuda-Ikedo Fig. 5)",
        5,
        camera([0.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        g,
    )
}

/// Fig. 7: a street light at night in light mist: the lamp hangs at the top of a
/// pole over a road; the original is drawn by the light-shafts pipeline (its cone in
/// the mist and the lit road), then the lamp gets bloom and a halo.
pub fn street_light() -> Scene {
    let lamp = [1.5, 5.0, -14.0];
    let mut s = source(SourceKind::Circle, lamp, 1500.0);
    s.a = 0.15;
    s.flare = false;
    s.color = [1.0, 0.9, 0.7];
    let mut g = section(Background::Shafts, vec![s]);
    g.determinants.mist = 0.2;
    // A dimmer veil than the default keeps the bloom below saturation at the halo's
    // radius, so the ring shows (as in the paper's right-hand panel).
    g.model.bloom_k = 0.3;
    g.model.halo_k = 0.08;
    Scene {
        chip: ChipPreset::GeForce2,
        name: "street-light: a street light at night (Matsuda-Ikedo Fig. 7)".into(),
        seed: 7,
        image: ImageSize::default(),
        camera: camera([0.0, 1.6, 0.0], [0.6, 3.2, -14.0]),
        medium: Medium {
            rho: 0.03,
            kappa: 0.8,
            k: 1.0,
        },
        lights: vec![Light {
            kind: LightKind::Spot,
            position: [lamp[0], lamp[1] - 0.2, lamp[2]],
            direction: [0.0, -1.0, 0.0],
            cutoff_deg: 35.0,
            intensity: 40.0,
            color: [1.0, 0.9, 0.7],
            light_map: Some(LightMap::Smooth { exponent: 1.0 }),
        }],
        objects: vec![
            Object {
                shape: Shape::Plane {
                    center: [1.0, 0.0, -18.0],
                    normal: [0.0, 1.0, 0.0],
                    tangent: [1.0, 0.0, 0.0],
                    half_size: [5.0, 12.0],
                },
                color: [0.35, 0.35, 0.38],
                occluder: false,
                material: None,
            },
            Object {
                shape: Shape::Box {
                    min: [lamp[0] + 0.3, 0.0, lamp[2] - 0.1],
                    max: [lamp[0] + 0.45, lamp[1] + 0.1, lamp[2] + 0.05],
                },
                color: [0.2, 0.2, 0.2],
                occluder: true,
                material: None,
            },
        ],
        shafts: ShaftsConfig::default(),
        glare: Some(g),
        rounding: None,
        shading_hw: None,
        shading_sphere: None,
        test_scene: None,
        environment: None,
    }
}

/// Fig. 8: sunlight through leaves: the sun behind a canopy, split into 12 patches
/// whose brightness follows independent 1/f chaos maps (eqs. 9–11).
pub fn leaves() -> Scene {
    let mut s = source(SourceKind::Circle, [0.0, 0.0, -20.0], 1500.0);
    s.a = 0.05;
    s.halo = false;
    s.color = [1.0, 0.97, 0.85];
    s.fluctuation = Some(Fluctuation {
        patches: 12,
        spread: 2.5,
        patch_radius: 0.05,
    });
    let mut g = section(
        Background::Canopy {
            leaves: 160,
            sky: [0.55, 0.7, 0.85],
            leaf: [0.08, 0.16, 0.05],
        },
        vec![s],
    );
    g.determinants.ambient = 20.0;
    glare_scene(
        "leaves: sunlight through leaves, 1/f flicker (Matsuda-Ikedo Fig. 8)",
        8,
        camera([0.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        g,
    )
}

/// A sphere on a floor under one bright point light, shaded by the shading units; the
/// glare conditions read the highlight the shader finds (`[glare.shaded_highlights]`),
/// no source is written by hand. `metal`: gold Cook–Torrance (Beckmann m = 0.15,
/// η = 0.27 + 2.8i), whose highlight passes Table 2's contrast rule and becomes a
/// glare source; otherwise a rough dielectric (GGX α = 0.5, η = 1.5) whose highlight
/// stays below it.
pub fn shaded_sphere(metal: bool) -> Scene {
    use super::glare::ShadedHighlights;
    use super::material::{Distribution, FresnelKind, Material};
    let material = if metal {
        Material::CookTorrance {
            distribution: Distribution::Beckmann,
            roughness: 0.15,
            ior: 0.27,
            extinction: 2.8,
            fresnel: FresnelKind::Exact,
        }
    } else {
        Material::CookTorrance {
            distribution: Distribution::Ggx,
            roughness: 0.5,
            ior: 1.5,
            extinction: 0.0,
            fresnel: FresnelKind::Exact,
        }
    };
    let mut glare = section(night(), vec![]);
    glare.shaded_highlights = Some(ShadedHighlights {
        light: 0,
        intensity: 600.0,
        radius: 0.03,
    });
    let mut s = glare_scene(
        if metal {
            "shaded-metal: a gold Cook-Torrance sphere whose own highlight becomes a glare source"
        } else {
            "shaded-dielectric: the same sphere as a rough dielectric: its highlight stays below the glare threshold"
        },
        13,
        camera([0.0, 1.6, 7.0], [0.0, 1.0, 0.0]),
        glare,
    );
    s.lights = vec![Light {
        kind: LightKind::Point,
        position: [-4.0, 6.0, 6.0],
        direction: [0.0, -1.0, 0.0],
        cutoff_deg: 20.0,
        intensity: 1.0,
        color: [1.0, 1.0, 1.0],
        light_map: None,
    }];
    s.objects = vec![
        Object {
            shape: Shape::Sphere {
                center: [0.0, 1.0, 0.0],
                radius: 1.0,
            },
            color: [0.45, 0.5, 0.6],
            occluder: true,
            material: Some(material),
        },
        Object {
            shape: Shape::Plane {
                center: [0.0, 0.0, 0.0],
                normal: [0.0, 1.0, 0.0],
                tangent: [1.0, 0.0, 0.0],
                half_size: [6.0, 6.0],
            },
            color: [0.25, 0.25, 0.25],
            occluder: false,
            material: None,
        },
    ];
    s
}

/// A glare built-in by name.
pub fn glare_builtin(name: &str) -> Option<Scene> {
    Some(match name {
        "glare-point" => glare_point(),
        "glare-elliptic" => glare_elliptic(),
        "glare-flare" => glare_flare(),
        "street-light" => street_light(),
        "leaves" => leaves(),
        "shaded-metal" => shaded_sphere(true),
        "shaded-dielectric" => shaded_sphere(false),
        _ => return None,
    })
}

/// The city at night of the glare scaling run (`reproduce glare-scaling`): `n` point
/// sources with bloom, seen from a hill over a 96 × 64 frame, of four kinds (street
/// lamps, windows, car lights, signs) at a few brightnesses each, placed with `seed`.
/// Sources of one kind and brightness share their tables; the frame's cost is then
/// the primitives drawn, linear in `n`.
pub fn city_lights(n: usize, seed: u64) -> Scene {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    // (intensity codes, colour, height above the ground in world units)
    let kinds: [([f64; 3], [f64; 3], f64); 4] = [
        ([1.6, 2.0, 2.4], [1.0, 0.72, 0.38], 6.0),
        ([0.6, 0.8, 1.0], [1.0, 0.9, 0.7], 12.0),
        ([1.0, 1.2, 1.4], [0.9, 0.95, 1.0], 0.6),
        ([0.8, 1.0, 1.2], [1.0, 0.35, 0.55], 4.0),
    ];
    let sources = (0..n)
        .map(|_| {
            let (levels, color, height) = kinds[rng.random_range(0..kinds.len())];
            let depth = 40.0 + 360.0 * rng.random::<f64>();
            let x = (2.0 * rng.random::<f64>() - 1.0) * 0.5 * depth;
            let y = height * rng.random::<f64>();
            let mut s = source(
                SourceKind::Point,
                [x, y, -depth],
                levels[rng.random_range(0..levels.len())],
            );
            s.color = color;
            s.halo = false;
            s.flare = false;
            s
        })
        .collect();
    let mut s = glare_scene(
        &format!("city-lights: {n} lights of a city at night"),
        seed,
        Camera {
            far: 1000.0,
            ..camera([0.0, 25.0, 0.0], [0.0, 0.0, -220.0])
        },
        section(night(), sources),
    );
    s.image = ImageSize {
        width: 96,
        height: 64,
    };
    s
}
