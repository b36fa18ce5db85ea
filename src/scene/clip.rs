//! Whether a scene needs the clipper, decided from the scene alone before any pass:
//! the camera, the image size and the objects. The sample planes need none: each
//! covers exactly the viewport (its corner vertex at (width, height), inside the
//! interpolator's range for every image size validation accepts). An object needs it
//! when a vertex of one of its triangles (as its shape gives them, before the host's
//! subdivision, whose vertices lie inside them) is outside a clip plane: behind the
//! near plane, beyond the far plane, or projecting outside the guard band (the
//! interpolator's screen range). A triangle inside every plane is convex on the
//! screen, so its subdivided triangles are inside too.

use super::camera::CameraView;
use super::format::Scene;
use super::limits;
use super::teapot::shape_triangles;
use rtl_model::units::clipper::{Clipper, PLANE_NAMES};
use rtl_model::Counters;

/// Why the scene's objects need the clipper (the first object and plane found), or
/// None when every object stays inside every plane. An object whose shape does not
/// tessellate is left to validation (None here).
pub fn clip_needed(scene: &Scene) -> Option<String> {
    let clipper = limits::shafts_clipper(scene).build().ok()?;
    clip_needed_with(scene, &clipper)
}

/// [`clip_needed`] against a given clipper's planes.
pub fn clip_needed_with(scene: &Scene, clipper: &Clipper) -> Option<String> {
    let cam = CameraView::new(&scene.camera, scene.image);
    let mut scratch = Counters::default();
    for (i, o) in scene.objects.iter().enumerate() {
        let Ok(tris) = shape_triangles(&o.shape) else {
            continue;
        };
        for t in &tris {
            for p in t.p {
                let c = cam.view_proj.apply(p);
                let Ok(v) = clipper.vertex_from_f64(0, c, &[], &mut scratch) else {
                    continue;
                };
                let code = clipper.outcode(&[v.x, v.y, v.z, v.w]);
                if code != 0 {
                    let plane = PLANE_NAMES[code.trailing_zeros() as usize];
                    return Some(format!(
                        "objects[{i}] crosses the {plane} {}",
                        if plane == "near" || plane == "far" {
                            "plane"
                        } else {
                            "edge of the guard band"
                        }
                    ));
                }
            }
        }
    }
    None
}
