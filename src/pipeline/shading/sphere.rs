//! The test object of the shading reproductions: a unit sphere seen orthographically
//! along −z, lit by one distant light. Every shading reproduction (`shading-brdfs`,
//! `shading-factorization`, `shading-specular`) measures its error on these pixels.

use crate::reference::brdf::{Brdf, ShadingFrame};
use crate::scene::math::{v3, Vec3};

/// The view: a `size` × `size` image of the unit sphere, viewer at +z (orthographic),
/// one distant light of irradiance `irradiance` (normal incidence) from `light`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereView {
    pub size: u32,
    /// Unit vector toward the light (world space).
    pub light: Vec3,
    /// Radiance scale: a pixel's 8-bit level is 255 · clamp(R · cos θ_i · irradiance).
    pub irradiance: f64,
}

impl Default for SphereView {
    /// 256 × 256, light from the upper left and slightly behind the viewer's side
    /// (so the highlight sits inside the disc and the rim shows grazing angles).
    fn default() -> Self {
        SphereView {
            size: 256,
            light: v3(-0.45, 0.55, 0.70).normalized(),
            irradiance: 1.0,
        }
    }
}

/// One covered pixel: its image position, shading frame, and the light and view
/// directions in that frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpherePixel {
    pub x: u32,
    pub y: u32,
    /// World-space frame: n the sphere normal, t the tangent along increasing
    /// longitude about the world y axis (so an anisotropic highlight stretches
    /// horizontally around the sphere).
    pub frame: ShadingFrame,
    /// ω_i and ω_o in the local frame (z = n, x = t).
    pub wi: Vec3,
    pub wo: Vec3,
}

/// The viewer direction (toward the viewer, world space).
pub const VIEW: Vec3 = v3(0.0, 0.0, 1.0);

impl SphereView {
    /// The world-space normal at a pixel centre, or None outside the disc.
    pub fn normal_at(&self, x: u32, y: u32) -> Option<Vec3> {
        let s = self.size as f64;
        let u = (x as f64 + 0.5) / s * 2.0 - 1.0;
        let v = 1.0 - (y as f64 + 0.5) / s * 2.0;
        let r2 = u * u + v * v;
        (r2 < 1.0).then(|| v3(u, v, (1.0 - r2).sqrt()))
    }

    /// Every pixel in row-major order; None outside the sphere.
    pub fn pixels(&self) -> Vec<Option<SpherePixel>> {
        let mut out = Vec::with_capacity((self.size * self.size) as usize);
        for y in 0..self.size {
            for x in 0..self.size {
                out.push(self.normal_at(x, y).map(|n| {
                    let frame = ShadingFrame::new(n, v3(0.0, 1.0, 0.0).cross(n));
                    SpherePixel {
                        x,
                        y,
                        frame,
                        wi: frame.to_local(self.light),
                        wo: frame.to_local(VIEW),
                    }
                }));
            }
        }
        out
    }

    /// The f64 reference radiance of a pixel: R(ω_i, ω_o) · max(cos θ_i, 0) · E.
    pub fn radiance(&self, brdf: &dyn Brdf, px: &SpherePixel) -> f64 {
        let cos_i = px.wi.z.max(0.0);
        if cos_i == 0.0 || px.wo.z <= 0.0 {
            return 0.0;
        }
        brdf.eval(px.wi, px.wo) * cos_i * self.irradiance
    }

    /// The reference image in 8-bit levels as f64 (unclamped above 255 is clamped;
    /// background 0), row-major.
    pub fn reference_levels(&self, brdf: &dyn Brdf) -> Vec<f64> {
        self.pixels()
            .iter()
            .map(|p| p.map_or(0.0, |p| (self.radiance(brdf, &p) * 255.0).clamp(0.0, 255.0)))
            .collect()
    }
}
