//! The scenes of the environment-map renders (the thesis §4.1): the camera, the sphere
//! and the Utah teapot, and the smoothness λ per vertex (uniform, or the thesis'
//! non-uniform settings). Re-exported by `super::render`.

use rtl_model::error::ConfigError;

use crate::scene::camera::CameraView;
use crate::scene::format::Camera;
use crate::scene::math::Vec3;
use crate::scene::teapot::{sphere_triangles, tessellate_teapot, Triangle};

/// Sphere tessellation (segments around y, rings pole to pole).
pub const SPHERE_SEGMENTS: u32 = 48;
pub const SPHERE_RINGS: u32 = 24;
/// Teapot: quads per patch side, scale.
pub const TEAPOT_SUBDIVISIONS: u32 = 6;
pub const TEAPOT_SCALE: f64 = 0.3;
/// Teapot height before scaling (y ∈ [0, 3.15]) and x extent (handle −3 to spout 3.434).
pub(super) const TEAPOT_HEIGHT: f64 = 3.15;
pub(super) const TEAPOT_X: (f64, f64) = (-3.0, 3.434);

/// The object drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Object {
    Sphere,
    Teapot,
}

impl Object {
    pub fn name(self) -> &'static str {
        match self {
            Object::Sphere => "sphere",
            Object::Teapot => "teapot",
        }
    }
}

/// The smoothness λ per vertex.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum LambdaSpec {
    /// The same λ ∈ [0, 1] everywhere.
    Uniform(f64),
    /// The thesis' non-uniform λ: the sphere's λ runs 0 → 1 around the view axis (6
    /// o'clock 0, 9 o'clock 0.25, 12 o'clock 0.5, 3 o'clock 0.75, seen from the camera);
    /// the teapot's runs linearly with height from 0.2 (bottom) to 0.9 (top).
    NonUniform,
}

impl LambdaSpec {
    /// The λ of every vertex when it is uniform (the 2D-slice elaboration's condition).
    pub fn uniform(&self) -> Option<f64> {
        match self {
            LambdaSpec::Uniform(l) => Some(*l),
            LambdaSpec::NonUniform => None,
        }
    }

    /// "1", "0.5", … or "nonuniform" (for the Table 5 rows).
    pub fn label(&self) -> String {
        match self {
            LambdaSpec::Uniform(l) => format!("{l}"),
            LambdaSpec::NonUniform => "nonuniform".to_string(),
        }
    }

    pub(super) fn validate(&self) -> Result<(), ConfigError> {
        if let LambdaSpec::Uniform(l) = *self {
            let l = rtl_model::error::check_finite("envmap_render.lambda", l)?;
            if !(0.0..=1.0).contains(&l) {
                return Err(ConfigError::out_of_range(
                    "envmap_render.lambda",
                    l,
                    0.0,
                    1.0,
                ));
            }
        }
        Ok(())
    }
}

/// The camera of every render (module notes): the thesis camera, which the built-in
/// environment scenes state too.
pub fn camera() -> Camera {
    crate::scene::environment::thesis_camera()
}

/// The object's triangles (world space) and per-vertex λ.
pub fn object_geometry(
    object: Object,
    lambda: LambdaSpec,
    cam: &CameraView,
) -> Result<Vec<(Triangle, [f64; 3])>, ConfigError> {
    lambda.validate()?;
    let (tris, lam): (Vec<Triangle>, Box<dyn Fn(Vec3) -> f64>) = match object {
        Object::Sphere => {
            let tris = sphere_triangles([0.0; 3], 1.0, SPHERE_SEGMENTS, SPHERE_RINGS)?;
            let (right, up) = (cam.right, cam.up);
            let f = move |p: Vec3| {
                // Angle around the view axis from 6 o'clock, through 9 (left), 12, 3.
                let (xr, yu) = (p.dot(right), p.dot(up));
                let a = (-xr).atan2(-yu).rem_euclid(std::f64::consts::TAU);
                (a / std::f64::consts::TAU).clamp(0.0, 1.0)
            };
            (tris, Box::new(f))
        }
        Object::Teapot => {
            let pos = teapot_position();
            let tris = tessellate_teapot(pos, TEAPOT_SCALE, 0.0, TEAPOT_SUBDIVISIONS)?;
            let (y0, h) = (pos[1], TEAPOT_HEIGHT * TEAPOT_SCALE);
            let f = move |p: Vec3| 0.2 + 0.7 * ((p.y - y0) / h).clamp(0.0, 1.0);
            (tris, Box::new(f))
        }
    };
    Ok(tris
        .into_iter()
        .map(|t| {
            let l = match lambda {
                LambdaSpec::Uniform(l) => [l; 3],
                LambdaSpec::NonUniform => [lam(t.p[0]), lam(t.p[1]), lam(t.p[2])],
            };
            (t, l)
        })
        .collect())
}

pub(super) fn teapot_position() -> [f64; 3] {
    [
        -0.5 * (TEAPOT_X.0 + TEAPOT_X.1) * TEAPOT_SCALE,
        -0.5 * TEAPOT_HEIGHT * TEAPOT_SCALE,
        0.0,
    ]
}
