//! Environment reflections inside a frame: each `environment.reflectors[i]` object is
//! tessellated and drawn from the scene's camera through the environment-map units
//! (interpolator → `reflection_vector` → the prefiltered map's sampler,
//! `envmap::render::render_geometry`), then scaled by its reflectance and the fog's
//! transmittance to the eye (one `modulate`, 8-bit). The object pass adds it
//! (saturating) to the object's shading.

use super::objects::Reflection;
use crate::chip::{PassKind, PassStats};
use crate::pipeline::envmap::render::{render_geometry, render_geometry_with_truth};
use crate::pipeline::envmap::scene_render::{build_map, render_options};
use crate::report::elaboration::Elaborated;
use crate::scene::camera::CameraView;
use crate::scene::format::Scene;
use crate::scene::geometry::{Ray, SceneGeometry};
use crate::scene::teapot::shape_triangles;
use rtl_model::driver::run_span;
use rtl_model::units::modulate::{Modulate, ModulateIn, ModulateMode};
use rtl_model::{ConfigError, Counters};
use std::collections::BTreeMap;

/// The reflections of the scene's reflectors (none without an environment section).
pub fn reflections(scene: &Scene) -> Result<Vec<Reflection>, ConfigError> {
    reflections_with(scene, false)
}

/// [`reflections`], and with `truth` each one's f64 reference: the Phong truth at its
/// pixels (`envmap::truth`, with the cos φ test) × reflectance × exp(−ρκT), unrounded.
pub fn reflections_with(scene: &Scene, truth: bool) -> Result<Vec<Reflection>, ConfigError> {
    let Some(section) = scene.environment.as_ref() else {
        return Ok(Vec::new());
    };
    if section.reflectors.is_empty() {
        return Ok(Vec::new());
    }
    let env = section.load()?;
    let (map, info) = build_map(section, &env)?;
    let mut opt = render_options(section);
    opt.exposure = Some(info.exposure);
    let (w, h) = (scene.image.width, scene.image.height);
    let cam = CameraView::new(&scene.camera, scene.image);
    let modulate = Modulate::new(8, ModulateMode::Exact)?;
    let m = scene.medium;
    let mut out = Vec::new();
    for (ri, r) in section.reflectors.iter().enumerate() {
        let field = format!("environment.reflectors[{ri}]");
        let tris: Vec<_> = shape_triangles(&scene.objects[r.object].shape)
            .map_err(|e| e.within(&format!("objects[{}]", r.object)))?
            .into_iter()
            .map(|t| (t, [r.lambda; 3]))
            .collect();
        let (img, info, mut counters, truth_img) = if truth {
            let (img, t, stats) =
                render_geometry_with_truth(&env, &map, &tris, &scene.camera, (w, h), &opt)
                    .map_err(|e| e.within(&field))?;
            (img, stats.frame, stats.counters, Some(t.cos_phi))
        } else {
            let (img, info, counters) =
                render_geometry(&env, &map, &tris, &scene.camera, (w, h), &opt)
                    .map_err(|e| e.within(&field))?;
            (img, info, counters, None)
        };
        let mut reference = truth_img.as_ref().map(|_| vec![None; (w * h) as usize]);
        let reflector = alone(&scene.objects[r.object]).map_err(|e| e.within(&field))?;
        // Reflectance × exp(−ρκT) per pixel (T: the eye distance along the pixel's ray
        // to the reflector, host f64 as a vertex colour would be), one 8-bit code.
        let mut at = Vec::new();
        let mut pairs = Vec::new();
        for (i, (&covered, px)) in img.mask.iter().zip(&img.pixels).enumerate() {
            if !covered {
                continue;
            }
            let (x, y) = ((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
            let t = hit_distance(&reflector, &cam, x, y);
            let k = r.reflectance * (-m.rho * m.kappa * t).exp();
            let code = (k.clamp(0.0, 1.0) * 255.0).round() as u32;
            if let (Some(refs), Some(ti)) = (reference.as_mut(), truth_img.as_ref()) {
                refs[i] = Some(ti.pixels[i].map(|v| v as f64 * k));
            }
            at.push(i);
            for c in px {
                pairs.push(ModulateIn {
                    a: *c as u32,
                    b: code,
                });
            }
        }
        let mut c = Counters::default();
        let scaled = run_span(&modulate, &mut (), &pairs, &mut c);
        *counters
            .entry("modulate (reflectance × transmittance)".into())
            .or_default() += c;
        let mut pixels = vec![None; (w * h) as usize];
        for (&i, v) in at.iter().zip(scaled.chunks(3)) {
            pixels[i] = Some([v[0], v[1], v[2]]);
        }
        let stats = PassStats {
            kind: PassKind::Objects,
            light: 0,
            walked: info.fragments,
            fragments: info.shaded,
            textures_per_fragment: 1,
            triangles: info.triangles as u64,
            texel_bytes: info.shaded * info.texels_per_lookup as u64 * 4,
            fb_bytes: info.shaded * 8,
            other_bytes: 0,
            depth_tests: info.fragments,
        };
        let elaboration = elaborated(&info.elaboration, ri);
        out.push(Reflection {
            object: r.object,
            pixels,
            reference,
            counters: prefixed(counters, ri),
            stats,
            elaboration,
        });
    }
    Ok(out)
}

/// The reflector's counters under `reflectors[i]: …`.
fn prefixed(c: BTreeMap<String, Counters>, i: usize) -> BTreeMap<String, Counters> {
    c.into_iter()
        .map(|(k, v)| (format!("reflectors[{i}]: {k}"), v))
        .collect()
}

/// The envmap renderer's sampler choice as elaboration rows.
fn elaborated(e: &crate::pipeline::envmap::slice::Elaboration, i: usize) -> Vec<Elaborated> {
    e.units
        .iter()
        .cloned()
        .map(|mut r| {
            r.name = format!("reflectors[{i}]: {}", r.name);
            r
        })
        .collect()
}

/// The reflector alone as ray-cast geometry (for its eye distances).
fn alone(object: &crate::scene::format::Object) -> Result<SceneGeometry, ConfigError> {
    SceneGeometry::without_meshes(std::slice::from_ref(object))
}

/// Distance from the eye to the geometry along the pixel's ray (0 if missed).
fn hit_distance(g: &SceneGeometry, cam: &CameraView, x: f64, y: f64) -> f64 {
    let ray = Ray {
        origin: cam.eye,
        dir: cam.ray_dir(x, y),
    };
    g.first_hit(&ray, cam.far).map_or(0.0, |(_, h)| h.t)
}
