//! The foundation test scene's definition (SPEC's built-in `test`): its sizes, the
//! checker and light-map texels, the camera and light transforms and the occluder.
//! The hardware render (`pipeline::test_scene`) and the f64 reference
//! (`reference::test_scene`) both read it from here, so neither imports the other.

use crate::scene::math::{v3, Mat4, Vec3};

/// Output size.
pub const WIDTH: u32 = 320;
pub const HEIGHT: u32 = 240;
/// Checker texture: 64 × 64 RGBA, 8 × 8 squares; repeated `CHECKER_REPEAT` times.
pub const CHECKER_SIZE: u32 = 64;
pub const CHECKER_REPEAT: f64 = 4.0;
/// Light map: 64 × 64 luminance spot.
pub const LIGHTMAP_SIZE: u32 = 64;
/// Floor: 10 × 10 world units, 8 × 8 cells (128 triangles).
pub const FLOOR_HALF: f64 = 5.0;
/// Ambient level (u8 unorm) and the light's colour.
pub const AMBIENT: u32 = 40;
pub const LIGHT_RGB: [u32; 3] = [255, 236, 200];
/// Lambert scale: N·L · LAMBERT_SCALE / d², clamped to 1.
pub const LAMBERT_SCALE: f64 = 42.0;

/// 64 × 64 RGBA checker: warm white and slate blue squares of 8 × 8 texels.
pub fn checker_texels() -> Vec<u32> {
    let mut t = Vec::with_capacity((CHECKER_SIZE * CHECKER_SIZE * 4) as usize);
    for y in 0..CHECKER_SIZE {
        for x in 0..CHECKER_SIZE {
            let c = if ((x / 8) + (y / 8)) % 2 == 0 {
                [235, 228, 210, 255]
            } else {
                [70, 96, 140, 255]
            };
            t.extend_from_slice(&c);
        }
    }
    t
}

/// 64 × 64 luminance spot: a smooth disc, 0 at the map's border (outside the cone),
/// with integer-only arithmetic so the table regenerates bit-exactly.
pub fn lightmap_texels() -> Vec<u32> {
    let n = LIGHTMAP_SIZE as i64;
    let mut t = Vec::with_capacity((n * n) as usize);
    for y in 0..n {
        for x in 0..n {
            // Distance² from the centre in half-texel units: (2x + 1 − n)² + (2y + 1 − n)².
            let (dx, dy) = (2 * x + 1 - n, 2 * y + 1 - n);
            let r2 = dx * dx + dy * dy;
            let inner = (n * 6 / 10).pow(2); // full intensity inside 0.3 of the map
            let outer = (n * 9 / 10).pow(2); // zero outside 0.45 of the map
            let v = if r2 <= inner {
                255
            } else if r2 >= outer {
                0
            } else {
                // Linear ramp in r² between the two radii.
                255 * (outer - r2) / (outer - inner)
            };
            t.push(v as u32);
        }
    }
    t
}

/// The scene's host-side set-up: camera and light transforms.
pub struct Views {
    pub cam: Mat4,
    pub light: Mat4,
    pub light_pos: Vec3,
}

pub fn views() -> Views {
    let aspect = WIDTH as f64 / HEIGHT as f64;
    let cam = Mat4::perspective(55.0, aspect, 0.5, 40.0).mul(&Mat4::look_at(
        v3(0.0, 7.0, 9.5),
        v3(0.0, 0.0, 0.3),
        v3(0.0, 1.0, 0.0),
    ));
    let light_pos = v3(1.5, 7.0, 0.5);
    let light = Mat4::perspective(60.0, 1.0, 1.0, 20.0).mul(&Mat4::look_at(
        light_pos,
        v3(-0.3, 0.0, 0.0),
        v3(0.0, 0.0, -1.0),
    ));
    Views {
        cam,
        light,
        light_pos,
    }
}

/// The occluder: a window frame (four bars and a cross) floating under the light.
pub fn occluder_quads() -> Vec<[Vec3; 4]> {
    let y = 4.2;
    let bar = |x0: f64, z0: f64, x1: f64, z1: f64| {
        [v3(x0, y, z0), v3(x1, y, z0), v3(x1, y, z1), v3(x0, y, z1)]
    };
    let (c, t, o) = (0.55, 0.09, 1.1); // centre offset, bar half-thickness, frame half-size
    vec![
        bar(-o, -o, o, -o + 2.0 * t),
        bar(-o, o - 2.0 * t, o, o),
        bar(-o, -o, -o + 2.0 * t, o),
        bar(o - 2.0 * t, -o, o, o),
        bar(-o, -t, o, t),
        bar(-t, -o, t, o),
    ]
    .into_iter()
    .map(|q| q.map(|p| p + v3(0.9 - c, 0.0, 0.1)))
    .collect()
}

/// `[test_scene]`: the foundation test scene's section. It has no fields (the scene
/// is fixed); its presence makes a scene the test scene.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TestSceneSection {}

/// The top-level table of the test scene's file form.
pub const FILE_TABLE: &str = "test_scene";

/// The test scene's file form (what `scene test` prints): it has no parameters, so
/// the `[test_scene]` table is empty; `scene::load::load_scene` reads it as
/// [`crate::scene::format::Scene::test_scene`], so `render --scene FILE` renders it as
/// `render --scene test` does.
pub fn file_toml() -> String {
    format!(
        "# The foundation test scene of glare-pipeline (`render --scene test`): a fixed\n\
         # {WIDTH} × {HEIGHT} scene that exercises every foundation unit: a checkered floor \
         ({CHECKER_SIZE}² RGBA\n\
         # checker), a spot with a {LIGHTMAP_SIZE}² light map and a shadow map, and a \
         window-frame occluder.\n\
         # It has no fields: this table names it, so `render --scene FILE` renders it.\n\
         # A scene of your own starts from a built-in instead: `glare-pipeline scene fig6`.\n\
         \n[{FILE_TABLE}]\n"
    )
}

/// Whether `text` is the test scene's file form (`Ok(false)`: another file form).
pub fn parse_file(text: &str) -> Result<bool, String> {
    let Ok(t) = text.parse::<toml::Table>() else {
        return Ok(false);
    };
    let Some(v) = t.get(FILE_TABLE) else {
        return Ok(false);
    };
    if let Some(k) = t.keys().find(|k| *k != FILE_TABLE) {
        return Err(format!(
            "{k}: a [{FILE_TABLE}] file holds nothing else (the test scene is fixed)"
        ));
    }
    match v.as_table() {
        Some(inner) if inner.is_empty() => Ok(true),
        Some(inner) => Err(format!(
            "{FILE_TABLE}.{}: the test scene has no fields (it is fixed)",
            inner.keys().next().map_or("", |k| k.as_str())
        )),
        None => Err(format!("{FILE_TABLE}: must be a table")),
    }
}
