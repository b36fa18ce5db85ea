//! From a validated scene to what the hardware frame needs: tessellated objects,
//! light-map texels, the ray geometry (for the plane range), and the reference's
//! geometry (built once, shared with the ray-marcher).

use super::prepare::{prepare, ObjectMesh, Prepared};
use crate::scene::format::{LightKind, Scene, Shape};
use crate::scene::geometry::{Ray, SceneGeometry, TriangleSoup};
use crate::scene::lightmap::rasterize_sampler;
use crate::scene::math::Vec3;
use crate::scene::teapot::{shape_triangles, tessellate_teapot};
use rtl_model::error::ConfigError;

/// The scene's ray geometry with teapots tessellated and light maps loaded.
pub fn scene_geometry(scene: &Scene) -> Result<SceneGeometry, ConfigError> {
    SceneGeometry::for_scene(scene, &mut |_i, shape| match shape {
        Shape::Teapot {
            position,
            scale,
            rotate_y_deg,
            subdivisions,
        } => {
            let tris = tessellate_teapot(*position, *scale, *rotate_y_deg, *subdivisions)?;
            Ok(Some(TriangleSoup {
                positions: tris.iter().map(|t| t.p).collect(),
                normals: Some(tris.iter().map(|t| t.n).collect()),
            }))
        }
        _ => Ok(None),
    })
}

/// Validate the scene and prepare a hardware frame (and the geometry it used).
pub fn prepare_scene(
    scene: &Scene,
    exposure: f64,
) -> Result<(Prepared, SceneGeometry), ConfigError> {
    scene.validate()?;
    prepare_scene_unchecked(scene, exposure)
}

/// [`prepare_scene`] without validating first: for tests that compare what validation
/// accepts with what the units accept (tests/limits.rs). Never for user input.
pub fn prepare_scene_unchecked(
    scene: &Scene,
    exposure: f64,
) -> Result<(Prepared, SceneGeometry), ConfigError> {
    let geom = scene_geometry(scene)?;
    let mut objects = Vec::with_capacity(scene.objects.len());
    for (i, o) in scene.objects.iter().enumerate() {
        let tris = shape_triangles(&o.shape).map_err(|e| e.within(&format!("objects[{i}]")))?;
        let max_edge = scene_extent(scene) / 24.0;
        objects.push(ObjectMesh {
            triangles: tris
                .into_iter()
                .flat_map(|t| subdivide((t.p, t.n), max_edge, 6))
                .collect(),
            color: o.color,
            occluder: o.occluder,
            colour_pass: !scene.shaded_object(i),
        });
    }
    // Spots always carry a light-map texture: a uniform spot's is the cone's disc.
    // Point lights have none (no projective unit; see docs/shafts.md).
    let light_maps = scene
        .lights
        .iter()
        .enumerate()
        .map(|(i, l)| match l.kind {
            LightKind::Spot => rasterize_sampler(
                geom.light_map(i),
                scene.shafts.light_map_texels,
                scene.shafts.texel_bits,
            )
            .map(Some)
            .map_err(|e| e.within(&format!("lights[{i}]"))),
            LightKind::Point => Ok(None),
        })
        .collect::<Result<Vec<_>, _>>()?;
    let first_hit = |o, d| {
        geom.first_hit(&Ray { origin: o, dir: d }, f64::INFINITY)
            .map(|(_, h)| h.t)
    };
    let p = prepare(scene, objects, light_maps, &first_hit, exposure);
    Ok((p, geom))
}

/// Size of the scene: the largest distance between the camera, the lights and the
/// objects' reference points.
fn scene_extent(scene: &Scene) -> f64 {
    let mut pts = vec![scene.camera.eye, scene.camera.look_at];
    pts.extend(scene.lights.iter().map(|l| l.position));
    let e = pts
        .iter()
        .flat_map(|a| {
            pts.iter().map(move |b| {
                ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
            })
        })
        .fold(0.0, f64::max);
    e.max(1e-6)
}

/// Split a triangle into four (edge midpoints, normals renormalised) until no edge is
/// longer than `max_edge` or `depth` runs out: the host's tessellation, so that the
/// per-vertex lighting (Gouraud, as the hardware shades) resolves the light's pool.
fn subdivide(t: ([Vec3; 3], [Vec3; 3]), max_edge: f64, depth: u32) -> Vec<([Vec3; 3], [Vec3; 3])> {
    let (p, n) = t;
    let longest = (0..3)
        .map(|i| (p[i] - p[(i + 1) % 3]).length())
        .fold(0.0, f64::max);
    if depth == 0 || longest <= max_edge {
        return vec![t];
    }
    let mid = |a: usize, b: usize| ((p[a] + p[b]) * 0.5, (n[a] + n[b]).normalized());
    let (p01, n01) = mid(0, 1);
    let (p12, n12) = mid(1, 2);
    let (p20, n20) = mid(2, 0);
    [
        ([p[0], p01, p20], [n[0], n01, n20]),
        ([p01, p[1], p12], [n01, n[1], n12]),
        ([p20, p12, p[2]], [n20, n12, n[2]]),
        ([p01, p12, p20], [n01, n12, n20]),
    ]
    .into_iter()
    .flat_map(|c| subdivide(c, max_edge, depth - 1))
    .collect()
}
