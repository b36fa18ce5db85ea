//! Equirectangular maps for the prefilter: texel directions and solid angles, the
//! 2 × 2 solid-angle-weighted pyramid, bilinear lookup by direction.
//!
//! Conventions (shared with `src/scene/envmap.rs`): width W along the longitude φ,
//! height H along the polar angle θ, measured from +y (row 0) to −y (row H − 1).
//! Texel (i, j) (column i, row j; stored row-major at `j * W + i`) has its centre at
//! φ = 2π(i + ½)/W and θ = π(j + ½)/H, direction
//! d = (sin θ sin φ, cos θ, −sin θ cos φ): φ = 0 looks along −z, φ = π/2 along +x,
//! φ = π along +z, φ = 3π/2 along −x (right-handed, y up). Its solid angle is
//! (2π/W)·(cos θ_top − cos θ_bottom) with θ_top = πj/H, θ_bottom = π(j + 1)/H; the
//! texels tile the sphere, so these sum to 4π (exactly, up to rounding).

use rtl_model::error::ConfigError;
use std::f64::consts::PI;

/// An owned equirectangular RGB map (linear radiance, any scale).
#[derive(Clone, Debug, PartialEq)]
pub struct Equirect {
    width: usize,
    height: usize,
    texels: Vec<[f64; 3]>,
}

impl Equirect {
    /// `texels` row-major, `width * height` of them; width, height ≥ 1. Non-finite
    /// radiance is refused (field `envmap_prefilter.texels`).
    pub fn new(width: usize, height: usize, texels: Vec<[f64; 3]>) -> Result<Self, ConfigError> {
        if width == 0 {
            return Err(ConfigError::invalid(
                "envmap_prefilter.width",
                "must be ≥ 1",
            ));
        }
        if height == 0 {
            return Err(ConfigError::invalid(
                "envmap_prefilter.height",
                "must be ≥ 1",
            ));
        }
        if width.checked_mul(height) != Some(texels.len()) {
            return Err(ConfigError::invalid(
                "envmap_prefilter.texels",
                &format!("{} texels for {width} × {height}", texels.len()),
            ));
        }
        if let Some(bad) = texels.iter().flatten().find(|v| !v.is_finite()) {
            return Err(ConfigError::not_finite("envmap_prefilter.texels", *bad));
        }
        Ok(Equirect {
            width,
            height,
            texels,
        })
    }

    /// A copy of a plain slice (e.g. another module's `EnvMap` texels).
    pub fn from_slice(
        width: usize,
        height: usize,
        texels: &[[f64; 3]],
    ) -> Result<Self, ConfigError> {
        Self::new(width, height, texels.to_vec())
    }

    /// A map whose texel (i, j) is `f(direction of its centre)`.
    pub fn from_fn(
        width: usize,
        height: usize,
        f: impl Fn([f64; 3]) -> [f64; 3],
    ) -> Result<Self, ConfigError> {
        let mut texels = Vec::with_capacity(width.saturating_mul(height));
        for j in 0..height {
            for i in 0..width {
                texels.push(f(texel_direction(i, j, width, height)));
            }
        }
        Self::new(width, height, texels)
    }

    pub fn width(&self) -> usize {
        self.width
    }
    pub fn height(&self) -> usize {
        self.height
    }
    pub fn texels(&self) -> &[[f64; 3]] {
        &self.texels
    }
    /// Texel (i, j); `i` wraps, `j` clamps (never panics).
    pub fn texel(&self, i: usize, j: usize) -> [f64; 3] {
        let j = j.min(self.height - 1);
        self.texels[j * self.width + i % self.width]
    }

    /// Σ Ω_texel · L over the map (per channel) and Σ Ω_texel (= 4π).
    pub fn solid_angle_sum(&self) -> ([f64; 3], f64) {
        let mut acc = [0.0; 3];
        let mut area = 0.0;
        for j in 0..self.height {
            let a = texel_solid_angle(j, self.width, self.height);
            let mut row = [0.0; 3];
            for l in &self.texels[j * self.width..(j + 1) * self.width] {
                for c in 0..3 {
                    row[c] += l[c];
                }
            }
            for c in 0..3 {
                acc[c] += a * row[c];
            }
            area += a * self.width as f64;
        }
        (acc, area)
    }

    /// The solid-angle-weighted mean radiance over the sphere.
    pub fn mean(&self) -> [f64; 3] {
        let (acc, area) = self.solid_angle_sum();
        acc.map(|v| v / area)
    }

    /// Half resolution: parent (i, j) = Σ Ω·L / Σ Ω over children (2i..2i+1, 2j..2j+1),
    /// Ω the child texel's solid angle. The two children in a row have equal Ω; the
    /// parent's Ω is the children's sum (the row edges coincide), so Σ Ω·L over the
    /// sphere is preserved and a constant map stays constant. Needs even W and H.
    pub fn downsample(&self) -> Result<Equirect, ConfigError> {
        if self.width < 2 || self.width & 1 != 0 {
            return Err(ConfigError::invalid(
                "envmap_prefilter.width",
                "must be even to downsample",
            ));
        }
        if self.height < 2 || self.height & 1 != 0 {
            return Err(ConfigError::invalid(
                "envmap_prefilter.height",
                "must be even to downsample",
            ));
        }
        let (w2, h2) = (self.width / 2, self.height / 2);
        let mut texels = Vec::with_capacity(w2 * h2);
        for j in 0..h2 {
            let a0 = texel_solid_angle(2 * j, self.width, self.height);
            let a1 = texel_solid_angle(2 * j + 1, self.width, self.height);
            let norm = 1.0 / (2.0 * (a0 + a1));
            for i in 0..w2 {
                let r0 = (2 * j) * self.width + 2 * i;
                let r1 = r0 + self.width;
                let mut p = [0.0; 3];
                for (c, pc) in p.iter_mut().enumerate() {
                    *pc = (a0 * (self.texels[r0][c] + self.texels[r0 + 1][c])
                        + a1 * (self.texels[r1][c] + self.texels[r1 + 1][c]))
                        * norm;
                }
                texels.push(p);
            }
        }
        Equirect::new(w2, h2, texels)
    }

    /// Bilinear lookup at direction `d` (any length; zero or non-finite → +y).
    /// Continuous texel coordinates u = φW/(2π) − ½, v = θH/π − ½; u wraps around
    /// the seam, v clamps to the first/last row (no crossing over the poles).
    pub fn sample_bilinear(&self, d: [f64; 3]) -> [f64; 3] {
        let (phi, theta) = direction_to_angles(d);
        let u = phi * self.width as f64 / (2.0 * PI) - 0.5;
        let v = theta * self.height as f64 / PI - 0.5;
        let uf = u.floor();
        let vf = v.floor();
        let fu = u - uf;
        let fv = v - vf;
        let w = self.width as i64;
        let h = self.height as i64;
        let i0 = (uf as i64).rem_euclid(w) as usize;
        let i1 = (uf as i64 + 1).rem_euclid(w) as usize;
        let j0 = (vf as i64).clamp(0, h - 1) as usize;
        let j1 = (vf as i64 + 1).clamp(0, h - 1) as usize;
        let t00 = self.texels[j0 * self.width + i0];
        let t10 = self.texels[j0 * self.width + i1];
        let t01 = self.texels[j1 * self.width + i0];
        let t11 = self.texels[j1 * self.width + i1];
        let mut out = [0.0; 3];
        for c in 0..3 {
            let top = t00[c] + fu * (t10[c] - t00[c]);
            let bot = t01[c] + fu * (t11[c] - t01[c]);
            out[c] = top + fv * (bot - top);
        }
        out
    }
}

/// The pyramid: level 0 is `base`, each next level [`Equirect::downsample`]d;
/// `levels` ≥ 1 maps in all (the thesis: 4, 512×256 → 64×32).
pub fn build_pyramid(base: &Equirect, levels: usize) -> Result<Vec<Equirect>, ConfigError> {
    if levels == 0 {
        return Err(ConfigError::invalid(
            "envmap_prefilter.levels",
            "must be ≥ 1",
        ));
    }
    let mut out = Vec::with_capacity(levels);
    out.push(base.clone());
    for _ in 1..levels {
        let next = out.last().map(Equirect::downsample).transpose()?;
        out.extend(next);
    }
    Ok(out)
}

/// Direction of texel (i, j)'s centre in a W × H map (unit length).
pub fn texel_direction(i: usize, j: usize, width: usize, height: usize) -> [f64; 3] {
    let phi = 2.0 * PI * (i as f64 + 0.5) / width.max(1) as f64;
    let theta = PI * (j as f64 + 0.5) / height.max(1) as f64;
    angles_to_direction(phi, theta)
}

/// d = (sin θ sin φ, cos θ, −sin θ cos φ).
pub fn angles_to_direction(phi: f64, theta: f64) -> [f64; 3] {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    [st * sp, ct, -st * cp]
}

/// (φ ∈ [0, 2π), θ ∈ [0, π]) of direction `d`; zero or non-finite `d` → +y (0, 0).
pub fn direction_to_angles(d: [f64; 3]) -> (f64, f64) {
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if !(len > 0.0 && len.is_finite()) {
        return (0.0, 0.0);
    }
    let y = (d[1] / len).clamp(-1.0, 1.0);
    let theta = y.acos();
    let mut phi = d[0].atan2(-d[2]);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    if phi >= 2.0 * PI {
        phi = 0.0;
    }
    (phi, theta)
}

/// Solid angle of a texel in row j of a W × H map: (2π/W)(cos θ_top − cos θ_bottom).
pub fn texel_solid_angle(j: usize, width: usize, height: usize) -> f64 {
    let h = height.max(1) as f64;
    let top = PI * j as f64 / h;
    let bottom = PI * (j as f64 + 1.0) / h;
    2.0 * PI / width.max(1) as f64 * (top.cos() - bottom.cos())
}
