//! The scene's pinhole camera: its `[camera]` and `[image]` sections ([`Camera`],
//! [`ImageSize`], re-exported by `format.rs`) and the camera as the host computes it
//! (f64): basis, projection, and the ray through a pixel. Shared by every pipeline (it
//! lives beside the scene, not inside one pipeline), and below the scene format and
//! the sections that name a camera.

use crate::scene::math::{v3, Mat4, Vec3};
use serde::{Deserialize, Serialize};

/// Output size in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImageSize {
    pub width: u32,
    pub height: u32,
}

impl Default for ImageSize {
    /// The paper's 720 × 480.
    fn default() -> Self {
        ImageSize {
            width: 720,
            height: 480,
        }
    }
}

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    pub eye: [f64; 3],
    pub look_at: [f64; 3],
    #[serde(default = "default_up")]
    pub up: [f64; 3],
    /// Vertical field of view, degrees, in (0, 180).
    #[serde(default = "default_fovy")]
    pub fovy_deg: f64,
    /// Near and far clip distances, 0 < near < far.
    #[serde(default = "default_near")]
    pub near: f64,
    #[serde(default = "default_far")]
    pub far: f64,
}

impl Camera {
    /// The camera of a scene that has none (a shading sphere, the test scene): eye
    /// and look-at at the origin, which no valid camera has (`camera.look_at` must
    /// differ from `camera.eye`). A scene of lights and objects without a camera is
    /// refused by validation, naming `camera`.
    pub fn unset() -> Camera {
        Camera {
            eye: [0.0; 3],
            look_at: [0.0; 3],
            up: default_up(),
            fovy_deg: default_fovy(),
            near: default_near(),
            far: default_far(),
        }
    }

    /// Whether this is [`Camera::unset`].
    pub fn is_unset(&self) -> bool {
        *self == Camera::unset()
    }
}

fn default_up() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}
fn default_fovy() -> f64 {
    45.0
}
fn default_near() -> f64 {
    0.1
}
fn default_far() -> f64 {
    100.0
}

/// Vec3 from a scene triple.
pub fn vec3(a: [f64; 3]) -> Vec3 {
    v3(a[0], a[1], a[2])
}

/// The camera: view and projection matrices and the orthonormal basis.
#[derive(Clone, Copy, Debug)]
pub struct CameraView {
    pub eye: Vec3,
    pub forward: Vec3,
    pub right: Vec3,
    pub up: Vec3,
    /// tan(fovy/2) and the aspect ratio.
    pub tan_half: f64,
    pub aspect: f64,
    pub width: u32,
    pub height: u32,
    pub near: f64,
    pub far: f64,
    pub view_proj: Mat4,
}

impl CameraView {
    pub fn new(c: &Camera, size: ImageSize) -> Self {
        let eye = vec3(c.eye);
        let forward = (vec3(c.look_at) - eye).normalized();
        let right = forward.cross(vec3(c.up)).normalized();
        let up = right.cross(forward);
        let aspect = size.width as f64 / size.height as f64;
        let view_proj = Mat4::perspective(c.fovy_deg, aspect, c.near, c.far).mul(&Mat4::look_at(
            eye,
            vec3(c.look_at),
            vec3(c.up),
        ));
        CameraView {
            eye,
            forward,
            right,
            up,
            tan_half: (c.fovy_deg.to_radians() / 2.0).tan(),
            aspect,
            width: size.width,
            height: size.height,
            near: c.near,
            far: c.far,
            view_proj,
        }
    }

    /// The world point at view depth `r` (distance along the view axis) seen at pixel
    /// position (px, py) (continuous, y down; pixel centres at k + ½).
    pub fn point_at(&self, px: f64, py: f64, r: f64) -> Vec3 {
        let nx = px / self.width as f64 * 2.0 - 1.0;
        let ny = 1.0 - py / self.height as f64 * 2.0;
        self.eye
            + (self.forward
                + self.right * (nx * self.tan_half * self.aspect)
                + self.up * (ny * self.tan_half))
                * r
    }

    /// Unit ray direction through pixel position (px, py).
    pub fn ray_dir(&self, px: f64, py: f64) -> Vec3 {
        (self.point_at(px, py, 1.0) - self.eye).normalized()
    }

    /// Screen position (pixels, y down) and window depth in [0, 1] of a world point;
    /// `None` behind the eye.
    pub fn project(&self, p: Vec3) -> Option<(f64, f64, f64)> {
        let c = self.view_proj.apply(p);
        if c[3] <= 1e-12 {
            return None;
        }
        let (x, y, z) = (c[0] / c[3], c[1] / c[3], c[2] / c[3]);
        Some((
            (x * 0.5 + 0.5) * self.width as f64,
            (0.5 - y * 0.5) * self.height as f64,
            z * 0.5 + 0.5,
        ))
    }

    /// View depth of a world point (distance along the view axis).
    pub fn depth_of(&self, p: Vec3) -> f64 {
        (p - self.eye).dot(self.forward)
    }
}
