//! The OpenGL 1.x lighting state as the host sets it (glLight, glMaterial,
//! glLightModel): plain f64 data, GL's defaults. The `vertex_lighting` unit loads it
//! into its registers; its f64 twin (`reference::vertex_lighting`) reads the same
//! values. No arithmetic here.

use serde::{Deserialize, Serialize};

/// One GL light (host values, eye space), GL_LIGHT0's defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Light {
    /// GL_POSITION (x, y, z, w): w = 0 directional (toward the light), else local at xyz/w.
    pub position: [f64; 4],
    /// GL_AMBIENT of the light, RGB, finite and ≥ 0 (default 0, 0, 0).
    pub ambient: [f64; 3],
    /// GL_DIFFUSE of the light, RGB, finite and ≥ 0 (default 1, 1, 1).
    pub diffuse: [f64; 3],
    /// GL_SPECULAR of the light, RGB, finite and ≥ 0 (default 1, 1, 1).
    pub specular: [f64; 3],
    /// GL_SPOT_DIRECTION, eye space, non-zero (normalised when loaded; default 0, 0, −1);
    /// read only when `spot_cutoff` is not 180.
    pub spot_direction: [f64; 3],
    /// GL_SPOT_EXPONENT, 0 ..= 10⁴ (GL allows 0 ..= 128; default 0).
    pub spot_exponent: f64,
    /// Degrees: 0 ..= 90, or 180 (no spot).
    pub spot_cutoff: f64,
    /// (constant, linear, quadratic).
    pub attenuation: [f64; 3],
}

impl Default for Light {
    fn default() -> Self {
        Light {
            position: [0.0, 0.0, 1.0, 0.0],
            ambient: [0.0; 3],
            diffuse: [1.0; 3],
            specular: [1.0; 3],
            spot_direction: [0.0, 0.0, -1.0],
            spot_exponent: 0.0,
            spot_cutoff: 180.0,
            attenuation: [1.0, 0.0, 0.0],
        }
    }
}

/// GL material (front face), GL's defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// GL_EMISSION, RGB, finite and ≥ 0 (default 0, 0, 0).
    pub emission: [f64; 3],
    /// GL_AMBIENT of the material, RGB, finite and ≥ 0 (default 0.2, 0.2, 0.2).
    pub ambient: [f64; 3],
    /// RGBA: the vertex alpha is the diffuse alpha.
    pub diffuse: [f64; 4],
    /// GL_SPECULAR of the material, RGB, finite and ≥ 0 (default 0, 0, 0).
    pub specular: [f64; 3],
    /// GL_SHININESS, the specular exponent, 0 ..= 10⁴ (GL allows 0 ..= 128; default 0).
    pub shininess: f64,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            emission: [0.0; 3],
            ambient: [0.2; 3],
            diffuse: [0.8, 0.8, 0.8, 1.0],
            specular: [0.0; 3],
            shininess: 0.0,
        }
    }
}

/// The lighting state the host loads: material, scene ambient, lights (≤ 8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LightingSetup {
    /// The front-face material.
    pub material: Material,
    /// GL_LIGHT_MODEL_AMBIENT, RGB, finite and ≥ 0 (default 0.2, 0.2, 0.2).
    pub scene_ambient: [f64; 3],
    /// The enabled lights, 0 ..= 8 (default: one GL_LIGHT0).
    pub lights: Vec<Light>,
}

impl Default for LightingSetup {
    fn default() -> Self {
        LightingSetup {
            material: Material::default(),
            scene_ambient: [0.2; 3],
            lights: vec![Light::default()],
        }
    }
}
