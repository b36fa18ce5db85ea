//! Host-side view set-up for the shafts pipeline: the camera and each light's
//! projection, as the application processor computes them (f64).

use crate::scene::format::Light;
use crate::scene::math::{v3, Mat4, Vec3};

pub use crate::scene::camera::{vec3, CameraView};

/// A spot light's projection: the square frustum circumscribing its cone, for the
/// shadow map and the projective light map.
#[derive(Clone, Copy, Debug)]
pub struct LightView {
    pub position: Vec3,
    pub axis: Vec3,
    pub view_proj: Mat4,
    pub near: f64,
    pub far: f64,
}

impl LightView {
    /// `near`/`far` bound the depths the shadow map resolves.
    pub fn new(l: &Light, near: f64, far: f64) -> Self {
        let position = vec3(l.position);
        let axis = vec3(l.direction).normalized();
        // A deterministic up vector not parallel to the axis.
        let up = if axis.y.abs() < 0.9 {
            v3(0.0, 1.0, 0.0)
        } else {
            v3(0.0, 0.0, -1.0)
        };
        let fov = (2.0 * l.cutoff_deg).clamp(1e-3, 179.0);
        let view_proj = Mat4::perspective(fov, 1.0, near, far).mul(&Mat4::look_at(
            position,
            position + axis,
            up,
        ));
        LightView {
            position,
            axis,
            view_proj,
            near,
            far,
        }
    }

    /// Homogeneous projective texture coordinates (s, t, r, q) of a world point:
    /// s/q, t/q ∈ [0, 1] across the cone's square (t down), r/q the window depth.
    pub fn strq(&self, p: Vec3) -> [f64; 4] {
        let c = self.view_proj.apply(p);
        [
            (c[0] + c[3]) * 0.5,
            (c[3] - c[1]) * 0.5,
            (c[2] + c[3]) * 0.5,
            c[3],
        ]
    }
}
