//! The shafts' ray-marching reference (Nishita 1987 style, the paper's "truth"):
//! per pixel, the camera ray, the first surface, and the single-scattering integral
//! I_s by the midpoint rule with a shadow ray at every sample (Dobashi et al. eqs. (1)–(4)).
//!
//! ## Exactly what is computed (the hardware pipeline uses the same formulas)
//! * **Camera ray.** Frame as `Mat4::look_at(eye, look_at, up)`: f = norm(look_at − eye),
//!   r = norm(f × up), u = r × f. Pixel (px, py) (row 0 at the top) has its centre at
//!   NDC x = 2(px + ½)/W − 1, y = 1 − 2(py + ½)/H, and the unit direction
//!   d = norm(f + r · x · tan(fovy/2) · W/H + u · y · tan(fovy/2)) — the inverse of
//!   `Mat4::perspective(fovy, W/H, near, far) · look_at`. t is the distance along d.
//! * **Far limit.** The far clip plane is a depth (as in GL): along d it lies at
//!   t_far = far / (d · f). A surface beyond it is clipped.
//! * **T** = the first hit distance (any object, occluder or not), or t_far if none.
//!   The integral runs over [0, T] (from the eye, not from the near plane).
//! * **I_o** at the hit P with unit normal N facing the eye and albedo ρ_d (the object's
//!   `color`): I_o = ρ_d ⊙ Σ_lights max(0, N · L̂) · I_l(P) · H(P) / max(s, S_MIN)², with
//!   L̂ = norm(light − P), s = |light − P|, I_l = intensity · colour · map (0 outside a
//!   spot's cone), H = 1 unless an occluder lies between P and the light, times the
//!   medium's attenuation between the light and the surface, exp(−ρκs) (the same
//!   extinction g applies to scattered light over s). No ambient term, no 1/π.
//!   I_o = 0 when no surface is hit.
//! * **I_v** = I_o · exp(−ρκT) + I_s.
//! * **I_s** = Σ_lights Σ_{k<N} H(t_k) · I_l(t_k) · F(α_k) · h(max(s_k, S_MIN), t_k) · Δt,
//!   t_k = a + (k + ½)Δt, Δt = (b − a)/N ([`crate::reference::shafts_model::g_clamped`]),
//!   where [a, b] is the part of [0, T] inside the light's cone
//!   ([`LightFrame::cone_interval`]; all of [0, T] for a point light). As in Nishita's
//!   method the ray is clipped to the light's illumination volume first, so all N
//!   samples fall where the integrand can be non-zero (outside the cone it is 0).
//!
//! Never NaN for a valid scene; a pixel with N = 0 samples has I_s = 0.
//! `raymarch_image` parallelises over rows (rayon) and collects rows in order; every
//! pixel is a pure function of its inputs, so the bytes do not depend on the thread
//! count.

// `!(x > 0.0)` is deliberate throughout: it is true for NaN, which must take the safe
// branch.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use rayon::prelude::*;

use crate::reference::shafts_model::{attenuation, cos_alpha, g_clamped, mul_no_nan, S_MIN};
use crate::scene::format::{Light, Medium, Scene};
use crate::scene::geometry::{Hit, Ray, SceneGeometry};
use crate::scene::lightmap::{LightFrame, LightMapSampler};
use crate::scene::math::{v3, Vec3};

/// Default exposure of [`to_levels`]: radiance 1.0 ↦ 255.
pub const DEFAULT_EXPOSURE: f64 = 255.0;

/// Radiance → 8-bit levels: c · exposure clamped to [0, 255] (unrounded; NaN → 0).
pub fn to_levels(radiance: [f64; 3], exposure: f64) -> [f64; 3] {
    radiance.map(|c| {
        let x = c * exposure;
        if x.is_nan() {
            0.0
        } else {
            x.clamp(0.0, 255.0)
        }
    })
}

/// The camera ray of a pixel and the far limit along it (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRay {
    pub ray: Ray,
    /// far / (d · f): where the far plane is along the ray.
    pub t_far: f64,
}

/// The camera ray through the centre of pixel (px, py). A degenerate camera (eye at
/// look_at, up parallel to the view) gives a zero direction and t_far = 0 (the pixel
/// is black), never NaN.
pub fn camera_ray(scene: &Scene, px: f64, py: f64) -> CameraRay {
    let c = &scene.camera;
    let eye = v3(c.eye[0], c.eye[1], c.eye[2]);
    let at = v3(c.look_at[0], c.look_at[1], c.look_at[2]);
    let up = v3(c.up[0], c.up[1], c.up[2]);
    let f = (at - eye).normalized();
    let r = f.cross(up).normalized();
    let u = r.cross(f);
    let (w, h) = (
        scene.image.width.max(1) as f64,
        scene.image.height.max(1) as f64,
    );
    let tan = (0.5 * c.fovy_deg.to_radians()).tan();
    let x = 2.0 * (px + 0.5) / w - 1.0;
    let y = 1.0 - 2.0 * (py + 0.5) / h;
    let d = (f + r * (x * tan * w / h) + u * (y * tan)).normalized();
    let cos = d.dot(f);
    let t_far = if cos > 0.0 && c.far.is_finite() {
        (c.far / cos).max(0.0)
    } else {
        0.0
    };
    CameraRay {
        ray: Ray {
            origin: eye,
            dir: d,
        },
        t_far: if t_far.is_nan() { 0.0 } else { t_far },
    }
}

/// Per-light data precomputed once per image.
#[derive(Clone, Debug)]
pub struct LightEval<'a> {
    pub light: &'a Light,
    pub frame: LightFrame,
    pub map: &'a LightMapSampler,
}

impl<'a> LightEval<'a> {
    pub fn all(scene: &'a Scene, geom: &'a SceneGeometry) -> Vec<LightEval<'a>> {
        scene
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| LightEval {
                light: l,
                frame: LightFrame::new(l),
                map: geom.light_map(i),
            })
            .collect()
    }

    /// intensity · map toward p (0 outside the cone), without the colour.
    pub fn weight(&self, p: Vec3) -> f64 {
        self.frame.weight(self.light.intensity, self.map, p)
    }
}

/// The scalar scattering integrand of one light at distance t along a camera ray:
/// H · (intensity · map) · F(α) · h(max(s, s_min), t). Multiply by the light's colour.
/// Returns 0 (no shadow ray) where the light does not emit toward the point.
pub fn scatter_integrand(
    le: &LightEval<'_>,
    medium: &Medium,
    geom: &SceneGeometry,
    ray: &Ray,
    t: f64,
    s_min: f64,
) -> f64 {
    let p = ray.at(t);
    let w = le.weight(p);
    if w == 0.0 {
        return 0.0;
    }
    let lp = le.frame.position;
    let s = (lp - p).length();
    let ca = cos_alpha(lp, p, ray.origin);
    let g = g_clamped(ca.acos(), s, t, medium, s_min);
    if g == 0.0 || geom.occluded(p, lp) {
        return 0.0;
    }
    mul_no_nan(w, g)
}

/// The object radiance I_o at a hit (see the module doc), before attenuation.
pub fn object_radiance(
    lights: &[LightEval<'_>],
    geom: &SceneGeometry,
    medium: &Medium,
    albedo: [f64; 3],
    hit: &Hit,
) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for le in lights {
        let lp = le.frame.position;
        let to = lp - hit.point;
        let s = to.length();
        let lambert = hit.normal.dot(to.normalized());
        if !(lambert > 0.0) {
            continue;
        }
        let w = le.weight(hit.point);
        if w == 0.0 || geom.occluded(hit.point, lp) {
            continue;
        }
        let sc = s.max(S_MIN);
        let k = mul_no_nan(mul_no_nan(w, lambert / (sc * sc)), attenuation(s, medium));
        for (c, acc) in sum.iter_mut().enumerate() {
            *acc += mul_no_nan(k, le.light.color[c]);
        }
    }
    std::array::from_fn(|c| mul_no_nan(albedo[c], sum[c]))
}

/// What a camera ray sees: T, the object index hit (if any) and the attenuated
/// object radiance I_o · exp(−ρκT).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primary {
    pub ray: Ray,
    pub t_end: f64,
    pub object: Option<usize>,
    pub surface: [f64; 3],
}

pub fn primary(
    scene: &Scene,
    geom: &SceneGeometry,
    lights: &[LightEval<'_>],
    px: f64,
    py: f64,
) -> Primary {
    let cr = camera_ray(scene, px, py);
    let (t_end, object, surface) = match geom.first_hit(&cr.ray, cr.t_far) {
        Some((i, hit)) => {
            let albedo = scene.objects.get(i).map(|o| o.color).unwrap_or([0.0; 3]);
            let io = object_radiance(lights, geom, &scene.medium, albedo, &hit);
            let a = attenuation(hit.t, &scene.medium);
            (hit.t, Some(i), io.map(|c| mul_no_nan(c, a)))
        }
        None => (cr.t_far, None, [0.0; 3]),
    };
    Primary {
        ray: cr.ray,
        t_end,
        object,
        surface,
    }
}

fn pixel_with(
    scene: &Scene,
    geom: &SceneGeometry,
    lights: &[LightEval<'_>],
    px: u32,
    py: u32,
    samples: u32,
) -> [f64; 3] {
    let pr = primary(scene, geom, lights, px as f64, py as f64);
    let mut out = pr.surface;
    if samples == 0 || !(pr.t_end > 0.0) {
        return out;
    }
    for le in lights {
        // Only the part of [0, T] inside the light's cone can scatter its light.
        let Some((a, b)) = le
            .frame
            .cone_interval(pr.ray.origin, pr.ray.dir, 0.0, pr.t_end)
        else {
            continue;
        };
        let dt = (b - a) / samples as f64;
        let mut sum = 0.0;
        for k in 0..samples {
            let t = a + (k as f64 + 0.5) * dt;
            sum += scatter_integrand(le, &scene.medium, geom, &pr.ray, t, S_MIN);
        }
        let v = mul_no_nan(sum, dt);
        for (c, o) in out.iter_mut().enumerate() {
            *o += mul_no_nan(v, le.light.color[c]);
        }
    }
    out
}

/// I_v of one pixel (linear RGB radiance) by the midpoint rule with `samples` samples.
pub fn raymarch_pixel(
    scene: &Scene,
    geom: &SceneGeometry,
    px: u32,
    py: u32,
    samples: u32,
) -> [f64; 3] {
    let lights = LightEval::all(scene, geom);
    pixel_with(scene, geom, &lights, px, py, samples)
}

/// The whole image (width · height pixels, row-major, row 0 at the top), linear RGB
/// radiance (scale to levels with [`to_levels`]). `geom` must be built from the same
/// scene ([`SceneGeometry::for_scene`]) so that image light maps are loaded.
pub fn raymarch_image(scene: &Scene, geom: &SceneGeometry, samples: u32) -> Vec<[f64; 3]> {
    let lights = LightEval::all(scene, geom);
    let (w, h) = (scene.image.width, scene.image.height);
    let rows: Vec<Vec<[f64; 3]>> = (0..h)
        .into_par_iter()
        .map(|py| {
            (0..w)
                .map(|px| pixel_with(scene, geom, &lights, px, py, samples))
                .collect()
        })
        .collect();
    rows.into_iter().flatten().collect()
}
