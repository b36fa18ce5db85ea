//! Host preparation of a scene for the shafts pipeline: the depth range the sample
//! planes must cover, and the ranges of the h table.

use super::view::{vec3, CameraView};
use crate::scene::format::{LightKind, Scene};
use crate::scene::math::Vec3;

/// A tessellated object as the host hands it to the pipeline.
#[derive(Clone, Debug)]
pub struct ObjectMesh {
    /// Triangles: positions and per-vertex unit normals.
    pub triangles: Vec<([Vec3; 3], [Vec3; 3])>,
    pub color: [f64; 3],
    pub occluder: bool,
    /// Coloured by this pipeline's object pass: true for a Lambert object without a
    /// material; an object with one is shaded by the shading units instead (it still
    /// enters the depth buffer and, as an occluder, the shadow maps).
    pub colour_pass: bool,
}

/// What the host prepares once per scene.
#[derive(Clone, Debug)]
pub struct Prepared {
    pub scene: Scene,
    pub objects: Vec<ObjectMesh>,
    /// Per light: light-map texels (`shafts.light_map_texels`², unorm texel_bits) or None
    /// (point lights).
    pub light_maps: Vec<Option<Vec<u32>>>,
    /// View depths bounding the lit volume: planes fill [r0, r1].
    pub plane_range: (f64, f64),
    /// h table ranges and the nearest light distance (sets h_ref).
    pub s_max: f64,
    pub t_max: f64,
    pub s_near: f64,
    /// Smallest scattering angle in the lit volume (sets the F table's full scale).
    pub alpha_min: f64,
    /// Output scale: radiance 1.0 = `exposure` 8-bit levels.
    pub exposure: f64,
}

impl Prepared {
    /// The α whose F is the F table's full scale: 0 (the table's maximum) or the lit
    /// volume's smallest scattering angle (`shafts.f_scale`).
    pub fn f_alpha(&self) -> f64 {
        match self.scene.shafts.f_scale {
            crate::scene::format::FScale::Table => 0.0,
            crate::scene::format::FScale::LitVolume => self.alpha_min,
        }
    }
}

/// Radiance 1.0 maps to this many 8-bit levels by default.
pub const DEFAULT_EXPOSURE: f64 = 255.0;

/// h is normalised at this percentile of the lit samples' light distances.
pub const NEAR_PERCENTILE: f64 = 0.0;

/// Is `p` inside light `l`'s cone (any point for a point light)?
pub fn in_cone(l: &crate::scene::format::Light, p: Vec3) -> bool {
    if l.kind == LightKind::Point {
        return true;
    }
    let d = p - vec3(l.position);
    let len = d.length();
    if len <= 0.0 {
        return true;
    }
    let axis = vec3(l.direction).normalized();
    d.dot(axis) / len >= l.cutoff_deg.to_radians().cos()
}

/// A point of the view frustum inside light `light`'s cone, in front of the first
/// surface: its ray `dir` through pixel (`px`, `py`), view depth `r`, eye distance `t`
/// and light distance `s`.
pub struct LitPoint {
    pub light: usize,
    pub p: Vec3,
    pub dir: Vec3,
    pub px: f64,
    pub py: f64,
    pub r: f64,
    pub t: f64,
    pub s: f64,
}

/// Visit the lit points sampled along rays through `rays` (fractions of the image's
/// width and height, in the order given) at `gz` view depths spread evenly over
/// [near, far] (cell centres), each ray until its first surface; per depth, the
/// lights in scene order.
pub fn for_each_lit_point(
    scene: &Scene,
    cam: &CameraView,
    rays: impl Iterator<Item = (f64, f64)>,
    gz: usize,
    first_hit: &dyn Fn(Vec3, Vec3) -> Option<f64>,
    mut f: impl FnMut(&LitPoint),
) {
    for (fx, fy) in rays {
        let (px, py) = (fx * cam.width as f64, fy * cam.height as f64);
        let dir = cam.ray_dir(px, py);
        let cos = dir.dot(cam.forward).max(1e-6);
        let t_hit = first_hit(cam.eye, dir).unwrap_or(f64::INFINITY);
        for iz in 0..gz {
            let r = cam.near + (cam.far - cam.near) * (iz as f64 + 0.5) / gz as f64;
            let t = r / cos;
            if t > t_hit {
                break;
            }
            let p = cam.eye + dir * t;
            for (light, l) in scene.lights.iter().enumerate() {
                if in_cone(l, p) {
                    let s = (p - vec3(l.position)).length();
                    f(&LitPoint {
                        light,
                        p,
                        dir,
                        px,
                        py,
                        r,
                        t,
                        s,
                    });
                }
            }
        }
    }
}

/// Ranges found by sampling the view frustum (a 48 × 32 grid of rays, 256 depths
/// each) for points inside some light's cone and in front of the first surface:
/// the plane range [r0, r1] (view depths), s_near (see below), s_max and t_max.
pub fn lit_ranges(scene: &Scene, first_hit: &dyn Fn(Vec3, Vec3) -> Option<f64>) -> LitRanges {
    let cam = CameraView::new(&scene.camera, scene.image);
    let (gx, gy, gz) = (48usize, 32usize, 256usize);
    let (mut r0, mut r1) = (f64::INFINITY, 0.0f64);
    let (mut s_max, mut t_max) = (0.0f64, 0.0f64);
    let mut cos_alpha_max = -1.0f64;
    let mut s_all: Vec<f64> = Vec::new();
    // The lit sample nearest a light: (s, px, py, r).
    let mut best = (f64::INFINITY, 0.0, 0.0, 0.0);
    let corners = (0..=gy)
        .flat_map(|iy| (0..=gx).map(move |ix| (ix as f64 / gx as f64, iy as f64 / gy as f64)));
    for_each_lit_point(scene, &cam, corners, gz, first_hit, |q| {
        let (s, t, p) = (q.s, q.t, q.p);
        if s < best.0 {
            best = (s, q.px, q.py, q.r);
        }
        r0 = r0.min(q.r);
        r1 = r1.max(q.r);
        s_all.push(s);
        // Scattering angle: cos α = L̂ · view direction (α = 0 forward).
        if s > 0.0 {
            let l_hat = (vec3(scene.lights[q.light].position) - p) * (1.0 / s);
            cos_alpha_max = cos_alpha_max.max(l_hat.dot(q.dir));
        }
        s_max = s_max.max(s);
        t_max = t_max.max(t);
    });
    if !r0.is_finite() {
        // Nothing lit is visible: one harmless interval at the near plane.
        return LitRanges {
            plane_range: (cam.near, cam.near * 2.0),
            s_near: 1.0,
            s_max: 1.0,
            t_max: cam.near * 2.0,
            alpha_min: 0.0,
        };
    }
    // h is stored relative to h(s_near): the NEAR_PERCENTILE-th percentile of the lit
    // samples' light distances (0: the nearest, refined below, so that before the cap no
    // fragment's h exceeds h_ref; a higher percentile would let the few samples next to
    // the cone's apex clamp, 1/s²).
    s_all.sort_by(f64::total_cmp);
    let s_near = s_all[(s_all.len() as f64 * NEAR_PERCENTILE) as usize];
    // The grid can pass up to half a cell from the true nearest point (next to a
    // light's apex the 1/s² peak is sharp): search the cells around the nearest sample
    // on a 16³ grid; h_ref then covers every fragment the planes can draw.
    let s_near = if NEAR_PERCENTILE == 0.0 {
        nearest_lit_around(scene, &cam, first_hit, best, (gx, gy, gz), s_near)
    } else {
        s_near
    };
    // A margin of a few depth steps and 3 % of the range on each side (the grid can
    // miss the cone's thin extremes).
    let step = (cam.far - cam.near) / gz as f64;
    let margin = 2.0 * step + 0.03 * (r1 - r0);
    let r0 = (r0 - margin).max(cam.near);
    let r1 = (r1 + margin).min(cam.far);
    LitRanges {
        plane_range: (r0, r1),
        s_near,
        s_max: s_max * 1.05 + step,
        t_max: t_max * 1.05 + step,
        alpha_min: cos_alpha_max.clamp(-1.0, 1.0).acos(),
    }
}

/// The smallest light distance of a lit point in the grid cells around the nearest
/// lit sample `best` = (s, px, py, r) of a `gx` × `gy` × `gz` grid: a 16³ grid over
/// ± one cell in x, y and view depth, starting from `s_near`.
fn nearest_lit_around(
    scene: &Scene,
    cam: &CameraView,
    first_hit: &dyn Fn(Vec3, Vec3) -> Option<f64>,
    best: (f64, f64, f64, f64),
    (gx, gy, gz): (usize, usize, usize),
    s_near: f64,
) -> f64 {
    let (cw, ch) = (cam.width as f64 / gx as f64, cam.height as f64 / gy as f64);
    let cz = (cam.far - cam.near) / gz as f64;
    let (_, bx, by, br) = best;
    let k = 16;
    let mut m = s_near;
    for a in 0..=k {
        for b in 0..=k {
            let px = bx + cw * (2.0 * a as f64 / k as f64 - 1.0);
            let py = by + ch * (2.0 * b as f64 / k as f64 - 1.0);
            let dir = cam.ray_dir(px, py);
            let cos = dir.dot(cam.forward).max(1e-6);
            let t_hit = first_hit(cam.eye, dir).unwrap_or(f64::INFINITY);
            for c in 0..=k {
                let r = (br + cz * (2.0 * c as f64 / k as f64 - 1.0)).max(cam.near);
                let t = r / cos;
                if t > t_hit {
                    break;
                }
                let p = cam.eye + dir * t;
                for l in &scene.lights {
                    if in_cone(l, p) {
                        m = m.min((p - vec3(l.position)).length());
                    }
                }
            }
        }
    }
    m
}

/// What [`lit_ranges`] finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LitRanges {
    pub plane_range: (f64, f64),
    pub s_near: f64,
    pub s_max: f64,
    pub t_max: f64,
    /// The smallest scattering angle seen in the lit volume: F is normalised by
    /// F(alpha_min), the largest phase value the planes meet.
    pub alpha_min: f64,
}

/// Assemble a prepared frame from host-side pieces.
pub fn prepare(
    scene: &Scene,
    objects: Vec<ObjectMesh>,
    light_maps: Vec<Option<Vec<u32>>>,
    first_hit: &dyn Fn(Vec3, Vec3) -> Option<f64>,
    exposure: f64,
) -> Prepared {
    let lit = lit_ranges(scene, first_hit);
    let s_max = if scene.shafts.s_max > 0.0 {
        scene.shafts.s_max
    } else {
        lit.s_max
    };
    let t_max = if scene.shafts.t_max > 0.0 {
        scene.shafts.t_max
    } else {
        lit.t_max
    };
    Prepared {
        scene: scene.clone(),
        objects,
        light_maps,
        plane_range: lit.plane_range,
        s_max,
        t_max,
        s_near: lit.s_near,
        alpha_min: lit.alpha_min,
        exposure,
    }
}
