//! The object pass of a scene through the shading units, and the highlights it finds:
//! every pixel whose camera ray meets an object is shaded by the object's material
//! path ([`super::path`]) for one scene light; for each object with a specular
//! material the brightest specular fragment becomes a [`Highlight`] for the glare
//! conditions (Table 2), with I_s = that fragment's specular level / 255 (full scale =
//! the radiance of a white Lambert surface lit head-on, E = π).
//!
//! Geometry is the host's: the ray through each pixel centre meets the scene's
//! shapes (spheres, rectangles, boxes; a teapot is an error naming its object), as the
//! depth pass would resolve them; shadows between objects are not cast in this pass
//! (each fragment sees the light unless it faces away from it, n·l ≤ 0). The shading
//! arithmetic is the units'.

use super::materials::material_path;
use super::path::{PathConfig, PathCounters, ShadingPath};
use crate::reference::brdf::ShadingFrame;
use crate::report::elaboration::Elaborated;
use crate::scene::camera::{vec3, CameraView};
use crate::scene::format::Scene;
use crate::scene::geometry::{Ray, SceneGeometry};
use crate::scene::glare::{Highlight, HighlightMaterial};
use crate::scene::material::Material;
use crate::scene::math::{v3, Vec3};
use rtl_model::ConfigError;

/// The brightest specular fragment of one object.
#[derive(Clone, Debug, PartialEq)]
pub struct FoundHighlight {
    pub object: usize,
    /// Pixel (x, y).
    pub pixel: [u32; 2],
    /// Its specular level (8-bit) and the highlight handed to the glare conditions.
    pub specular: u32,
    pub highlight: Highlight,
}

/// The shaded objects of a scene.
pub struct SceneShading {
    /// Per pixel: the shaded RGB levels (8-bit) where an object is hit, else None.
    pub pixels: Vec<Option<[u32; 3]>>,
    pub highlights: Vec<FoundHighlight>,
    pub counters: PathCounters,
    /// Per object with a path: what its path elaborated and left out.
    pub elaboration: Vec<Elaborated>,
    /// Fragments shaded.
    pub fragments: u64,
    /// Per pixel: the object whose surface was shaded there, else None.
    pub objects: Vec<Option<usize>>,
    /// Per pixel: the specular level (8-bit) of the shaded fragment, 0 where none.
    pub speculars: Vec<u32>,
}

/// Shade every object of `scene` lit by `lights[light]`; find a highlight per
/// specular object. `intensity` and `radius` go into the highlights (Table 2's I,
/// the glare disc's radius). Errors name the scene field.
pub fn shade_scene(
    scene: &Scene,
    light: usize,
    intensity: f64,
    radius: f64,
) -> Result<SceneShading, ConfigError> {
    shade_objects(scene, light, intensity, radius, &|_| true)
}

/// The shading path's configuration in a scene's frame: its `[rounding]` and its
/// `[shading_hw]` widths (each the GeForce default without the section).
pub fn path_config(scene: &Scene) -> PathConfig {
    let mut cfg = PathConfig {
        rounding: crate::scene::limits::GlRounding::of(scene),
        ..PathConfig::default()
    };
    if let Some(hw) = scene.shading_hw {
        cfg.cube.face_side = hw.cube_face;
        cfg.lookup.table_log2 = hw.lookup_log2;
        cfg.factor_resolution = hw.factor_size;
        cfg.factor_bits = hw.factor_bits;
    }
    cfg
}

/// [`shade_scene`] for the objects `selected` accepts: a pixel whose nearest object is
/// not selected is left to another pass (None), and costs no shading work.
pub fn shade_objects(
    scene: &Scene,
    light: usize,
    intensity: f64,
    radius: f64,
    selected: &dyn Fn(usize) -> bool,
) -> Result<SceneShading, ConfigError> {
    let lp = scene
        .lights
        .get(light)
        .map(|l| vec3(l.position))
        .ok_or_else(|| ConfigError::invalid("glare.shaded_highlights.light", "no such light"))?;
    let cfg = path_config(scene);
    let paths: Vec<ShadingPath> = scene
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| {
            material_path(&o.material.unwrap_or(Material::Lambert), o.color, &cfg)
                .map_err(|e| e.within(&format!("objects[{i}]")))
        })
        .collect::<Result<_, _>>()?;
    let geometry = SceneGeometry::without_meshes(&scene.objects)?;
    let cam = CameraView::new(&scene.camera, scene.image);
    let (w, h) = (scene.image.width, scene.image.height);
    let mut per_object: Vec<PathCounters> = vec![PathCounters::new(); scene.objects.len()];
    let mut pixels = Vec::with_capacity((w * h) as usize);
    let mut best: Vec<Option<FoundHighlight>> = vec![None; scene.objects.len()];
    let mut fragments = 0u64;
    let mut objects = Vec::with_capacity((w * h) as usize);
    let mut speculars = vec![0u32; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let dir = cam.ray_dir(x as f64 + 0.5, y as f64 + 0.5);
            let ray = Ray {
                origin: cam.eye,
                dir,
            };
            let Some((obj, hit)) = geometry
                .first_hit(&ray, cam.far)
                .filter(|(o, _)| selected(*o))
            else {
                pixels.push(None);
                objects.push(None);
                continue;
            };
            fragments += 1;
            objects.push(Some(obj));
            let frame = ShadingFrame::new(hit.normal, v3(0.0, 1.0, 0.0).cross(hit.normal));
            let to_light = (lp - hit.point).normalized();
            let to_eye = -dir;
            let s = paths[obj].shade(&frame, to_light, to_eye, &mut per_object[obj])?;
            pixels.push(Some(s.rgb));
            speculars[(y * w + x) as usize] = s.specular;
            let material = scene.objects[obj].material.unwrap_or(Material::Lambert);
            // Strictly brighter: ties keep the first fragment in raster order.
            let brighter = match &best[obj] {
                Some(b) => s.specular > b.specular,
                None => true,
            };
            if material.has_specular() && s.specular > 0 && brighter {
                best[obj] = Some(FoundHighlight {
                    object: obj,
                    pixel: [x, y],
                    specular: s.specular,
                    highlight: highlight(hit.point, hit.normal, lp, intensity, s.specular, radius),
                });
            }
        }
    }
    // Each object's path is its own set of stages (a pass per material).
    let mut counters = PathCounters::new();
    for (i, (p, mut c)) in paths
        .iter()
        .zip(per_object)
        .enumerate()
        .filter(|(i, _)| selected(*i))
    {
        p.close_counters(&mut c);
        for (name, c) in c {
            counters.insert(format!("objects[{i}]: {name}"), c);
        }
    }
    let mut elaboration = Vec::new();
    for (i, p) in paths.iter().enumerate().filter(|(i, _)| selected(*i)) {
        for mut e in p.elaboration(fragments) {
            e.name = format!("objects[{i}]: {}", e.name);
            elaboration.push(e);
        }
    }
    Ok(SceneShading {
        pixels,
        highlights: best.into_iter().flatten().collect(),
        counters,
        elaboration,
        fragments,
        objects,
        speculars,
    })
}

/// The glare conditions' input for a fragment: Table 2's metallic rule (every solid
/// surface seen from air: the water rule needs total internal reflection, which light
/// reflected off a solid object does not undergo), I_s the shader's specular level.
pub fn highlight(
    position: Vec3,
    normal: Vec3,
    light: Vec3,
    intensity: f64,
    specular: u32,
    radius: f64,
) -> Highlight {
    Highlight {
        material: HighlightMaterial::Metallic,
        position: [position.x, position.y, position.z],
        normal: [normal.x, normal.y, normal.z],
        light: [light.x, light.y, light.z],
        intensity,
        specular: specular as f64 / 255.0,
        eta: 1.33,
        radius,
    }
}
