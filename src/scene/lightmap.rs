//! Light maps (the spot's I_l distribution) in f64, the spot projection that maps a
//! point to map coordinates, and the rasterisation of a map into the hardware's
//! light-map texture.
//!
//! ## The spot projection
//! A spot's frame is `forward` = norm(direction), `right` = norm(forward × up_hint),
//! `up` = right × forward, with up_hint = +y, or +z when |forward · y| > 0.999 —
//! exactly the frame of `Mat4::look_at(position, position + forward, up_hint)`
//! (camera x = right, y = up, looking down −z = forward). A point p with light-frame
//! coordinates x = (p − L)·right, y = (p − L)·up, z = (p − L)·forward > 0 has map
//! coordinates
//!
//!   u = ½ + ½ · x / (z · tan c),  v = ½ − ½ · y / (z · tan c)    (c = cutoff)
//!
//! i.e. the perspective projection with a 90°-aspect-1 frustum of half-angle c (the
//! square circumscribing the cone), u to the right, v *down* (image rows, v = 0 is the
//! top row of an image map) — the same s = (x + w)/2, t = (w − y)/2 convention as the
//! built-in test scene with `Mat4::perspective(2c, 1, …)`. The cone is the disc
//! inscribed in the square: r² = (2u − 1)² + (2v − 1)² ≤ 1, for every map type.
//!
//! ## Map types (value in [0, 1])
//! * none (uniform): 1.
//! * `Smooth { exponent }`: (1 − r²)^exponent for r < 1, 0 for r ≥ 1 (exponent 0 gives 1
//!   inside the open disc).
//! * `PolkaDots { dots, radius }`: the smooth spot with exponent 1 times a mask that is 1
//!   inside (or on the rim of) a disc of radius `radius` · (cell side) centred in each
//!   cell of the `dots × dots` grid over [0, 1]², 0 elsewhere. **Hard edges**: the mask
//!   is a 0/1 stencil, as a painted gobo would be; the rasterised texture samples it at
//!   texel centres, so its edges are as hard as the texel grid allows.
//! * `Image { path }`: the image's luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of the
//!   stored values scaled to [0, 1] (no sRGB decoding; alpha ignored), sampled
//!   bilinearly between texel centres ((i + ½)/w, (j + ½)/h) with clamp-to-edge.
//!   Relative paths are relative to the working directory.

use std::path::Path;

use rtl_model::error::ConfigError;

use crate::scene::format::{Light, LightKind, LightMap};
use crate::scene::math::{v3, Vec3};

/// An evaluable light map (images are loaded once).
#[derive(Clone, Debug, PartialEq)]
pub enum LightMapSampler {
    Uniform,
    Smooth {
        exponent: f64,
    },
    PolkaDots {
        dots: u32,
        radius: f64,
    },
    Image {
        width: usize,
        height: usize,
        /// Row-major luminance in [0, 1], row 0 at v = 0.
        luma: Vec<f64>,
    },
}

impl LightMapSampler {
    /// Validate (and for images, load) a light map. Errors name `field_prefix` +
    /// `.exponent` / `.dots` / `.radius` / `.path`, e.g. `lights[2].light_map.path`.
    pub fn new(map: Option<&LightMap>, field_prefix: &str) -> Result<Self, ConfigError> {
        let f = |name: &str| format!("{field_prefix}.{name}");
        match map {
            None => Ok(LightMapSampler::Uniform),
            Some(LightMap::Smooth { exponent }) => {
                let e = *exponent;
                if !e.is_finite() {
                    return Err(ConfigError::not_finite(&f("exponent"), e));
                }
                if !(0.0..=1e6).contains(&e) {
                    return Err(ConfigError::out_of_range(&f("exponent"), e, 0.0, 1e6));
                }
                Ok(LightMapSampler::Smooth { exponent: e })
            }
            Some(LightMap::PolkaDots { dots, radius }) => {
                rtl_model::error::check_range(&f("dots"), *dots as u64, 1, 4096)?;
                let r = *radius;
                if !r.is_finite() {
                    return Err(ConfigError::not_finite(&f("radius"), r));
                }
                if !(r > 0.0 && r <= 0.5) {
                    return Err(ConfigError::out_of_range(&f("radius"), r, 0.0, 0.5));
                }
                Ok(LightMapSampler::PolkaDots {
                    dots: *dots,
                    radius: r,
                })
            }
            Some(LightMap::Image { path }) => load_image(Path::new(path), &f("path")),
        }
    }

    /// The sampler of `lights[index]` (errors name `lights[index].light_map.…`).
    pub fn for_light(light: &Light, index: usize) -> Result<Self, ConfigError> {
        Self::new(
            light.light_map.as_ref(),
            &format!("lights[{index}].light_map"),
        )
    }

    /// An image map from luminance values in [0, 1] (row-major, row 0 at v = 0).
    /// Values are clamped to [0, 1] (NaN → 0). Errors if the size does not match or is 0.
    pub fn from_luma(
        width: usize,
        height: usize,
        luma: Vec<f64>,
        field: &str,
    ) -> Result<Self, ConfigError> {
        if width == 0 || height == 0 || luma.len() != width * height {
            return Err(ConfigError::invalid(
                field,
                &format!(
                    "image of {width} × {height} with {} values is empty or inconsistent",
                    luma.len()
                ),
            ));
        }
        let luma = luma
            .into_iter()
            .map(|x| if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) })
            .collect();
        Ok(LightMapSampler::Image {
            width,
            height,
            luma,
        })
    }

    /// The map value at (u, v) (any finite or infinite input; NaN → 0). The cone mask
    /// (r ≤ 1) is *not* applied here except where the map itself vanishes (smooth,
    /// polka dots); [`light_weight`] applies it for every type.
    pub fn eval(&self, u: f64, v: f64) -> f64 {
        if u.is_nan() || v.is_nan() {
            return 0.0;
        }
        match self {
            LightMapSampler::Uniform => 1.0,
            LightMapSampler::Smooth { exponent } => smooth(u, v, *exponent),
            LightMapSampler::PolkaDots { dots, radius } => {
                let s = smooth(u, v, 1.0);
                if s == 0.0 {
                    return 0.0;
                }
                if polka_inside(u, v, *dots, *radius) {
                    s
                } else {
                    0.0
                }
            }
            LightMapSampler::Image {
                width,
                height,
                luma,
            } => bilinear(luma, *width, *height, u, v),
        }
    }

    /// A discrete label of the map's piecewise-constant structure at (u, v): changes
    /// exactly where the map may jump (polka-dot rims and cell changes). 0 for maps
    /// without jumps. Used by the adaptive quadrature to find breakpoints.
    pub fn discontinuity_label(&self, u: f64, v: f64) -> u64 {
        match self {
            LightMapSampler::PolkaDots { dots, radius } => {
                if u.is_nan() || v.is_nan() {
                    return 0;
                }
                let n = *dots as f64;
                let cx = (u * n).floor().clamp(-1.0, n) as i64 + 1;
                let cy = (v * n).floor().clamp(-1.0, n) as i64 + 1;
                let inside = polka_inside(u, v, *dots, *radius) as u64;
                1 + inside + 2 * (cx as u64 + (n as u64 + 2) * cy as u64)
            }
            _ => 0,
        }
    }
}

/// (1 − r²)^e inside the disc, 0 outside; r² = (2u − 1)² + (2v − 1)².
fn smooth(u: f64, v: f64, exponent: f64) -> f64 {
    let r2 = map_r2(u, v);
    if r2 >= 1.0 {
        0.0
    } else {
        (1.0 - r2).powf(exponent)
    }
}

/// r² of map coordinates: ((u − ½)² + (v − ½)²) / (½)².
pub fn map_r2(u: f64, v: f64) -> f64 {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    a * a + b * b
}

fn polka_inside(u: f64, v: f64, dots: u32, radius: f64) -> bool {
    let n = dots as f64;
    let (x, y) = (u * n, v * n);
    let (fx, fy) = (x - x.floor() - 0.5, y - y.floor() - 0.5);
    fx * fx + fy * fy <= radius * radius
}

fn bilinear(luma: &[f64], w: usize, h: usize, u: f64, v: f64) -> f64 {
    let coord = |c: f64, n: usize| {
        let x = (c * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
        let i0 = x.floor() as usize;
        let i1 = (i0 + 1).min(n - 1);
        (i0, i1, x - i0 as f64)
    };
    let (x0, x1, fx) = coord(u, w);
    let (y0, y1, fy) = coord(v, h);
    let at = |x: usize, y: usize| luma[y * w + x];
    let top = at(x0, y0) * (1.0 - fx) + at(x1, y0) * fx;
    let bot = at(x0, y1) * (1.0 - fx) + at(x1, y1) * fx;
    top * (1.0 - fy) + bot * fy
}

fn load_image(path: &Path, field: &str) -> Result<LightMapSampler, ConfigError> {
    let img = image::open(path).map_err(|e| {
        ConfigError::invalid(field, &format!("cannot read '{}': {e}", path.display()))
    })?;
    let rgb = img.to_rgb32f();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    let luma = rgb
        .pixels()
        .map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64)
        .collect();
    LightMapSampler::from_luma(w, h, luma, field)
}

/// A light's position and (for a spot) its projection frame, precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightFrame {
    pub position: Vec3,
    pub kind: LightKind,
    pub right: Vec3,
    pub up: Vec3,
    pub forward: Vec3,
    /// tan(cutoff); the spot emits nothing (every point maps to `None`) unless this is
    /// finite and > 0 and the direction is non-zero.
    pub tan_cutoff: f64,
    valid: bool,
}

impl LightFrame {
    pub fn new(light: &Light) -> Self {
        let [px, py, pz] = light.position;
        let position = v3(px, py, pz);
        let [dx, dy, dz] = light.direction;
        let forward = v3(dx, dy, dz).normalized();
        let hint = if forward.y.abs() > 0.999 {
            v3(0.0, 0.0, 1.0)
        } else {
            v3(0.0, 1.0, 0.0)
        };
        let right = forward.cross(hint).normalized();
        let up = right.cross(forward);
        let tan_cutoff = light.cutoff_deg.to_radians().tan();
        let valid = forward.length() > 0.5
            && light.cutoff_deg > 0.0
            && light.cutoff_deg < 90.0
            && tan_cutoff.is_finite()
            && tan_cutoff > 0.0;
        LightFrame {
            position,
            kind: light.kind,
            right,
            up,
            forward,
            tan_cutoff,
            valid,
        }
    }

    /// Map coordinates of p (see the module doc), not clamped to [0, 1]². `None` when
    /// p is behind the light or in its plane (z ≤ 0), for an invalid spot (zero
    /// direction, cutoff outside (0°, 90°)), and for a point light.
    pub fn map_coords(&self, p: Vec3) -> Option<(f64, f64)> {
        if self.kind != LightKind::Spot || !self.valid {
            return None;
        }
        let d = p - self.position;
        let z = d.dot(self.forward);
        if z.is_nan() || z <= 0.0 {
            return None;
        }
        let scale = 0.5 / (z * self.tan_cutoff);
        if !scale.is_finite() {
            return None;
        }
        let u = 0.5 + d.dot(self.right) * scale;
        let v = 0.5 - d.dot(self.up) * scale;
        if u.is_nan() || v.is_nan() {
            None
        } else {
            Some((u, v))
        }
    }

    /// The part of the segment origin + t·dir, t ∈ [t0, t1], inside the spot's cone
    /// (z > 0 and x² + y² ≤ z²·tan²(cutoff) in the light's frame), as (a, b). A ray meets
    /// the forward nappe of a cone narrower than 90° (a convex set) in one interval.
    /// `None` when the segment misses the cone or the spot is invalid; the whole segment
    /// for a point light. The breakpoints are the roots of the cone's quadratic and the
    /// crossing of the light's plane; each piece between breakpoints is classified by
    /// its midpoint, so tangent and through-the-apex rays need no special case.
    pub fn cone_interval(&self, origin: Vec3, dir: Vec3, t0: f64, t1: f64) -> Option<(f64, f64)> {
        // NaN bounds take this branch too.
        if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        if self.kind == LightKind::Point {
            return Some((t0, t1));
        }
        if !self.valid {
            return None;
        }
        let w = origin - self.position;
        let (wx, wy, wz) = (w.dot(self.right), w.dot(self.up), w.dot(self.forward));
        let (ex, ey, ez) = (dir.dot(self.right), dir.dot(self.up), dir.dot(self.forward));
        let k = self.tan_cutoff * self.tan_cutoff;
        // Q(t) = A t² + 2B t + C ≤ 0 inside the double cone.
        let a = ex * ex + ey * ey - k * ez * ez;
        let b = wx * ex + wy * ey - k * wz * ez;
        let c = wx * wx + wy * wy - k * wz * wz;
        let mut cuts = vec![t0, t1];
        let mut push = |t: f64| {
            if t.is_finite() && t > t0 && t < t1 {
                cuts.push(t);
            }
        };
        let scale = ex * ex + ey * ey + k * ez * ez;
        if a.abs() > 1e-12 * scale {
            let disc = b * b - a * c;
            if disc >= 0.0 {
                // Stable roots: q = −(B + sign(B)·√disc); t = q/A and C/q.
                let q = -(b + b.signum() * disc.sqrt());
                push(q / a);
                if q != 0.0 {
                    push(c / q);
                }
            }
        } else if b != 0.0 {
            push(-c / (2.0 * b));
        }
        if ez != 0.0 {
            push(-wz / ez);
        }
        cuts.sort_by(f64::total_cmp);
        let inside = |t: f64| {
            let (x, y, z) = (wx + t * ex, wy + t * ey, wz + t * ez);
            z > 0.0 && x * x + y * y <= k * z * z
        };
        let mut out: Option<(f64, f64)> = None;
        for p in cuts.windows(2) {
            if p[1] > p[0] && inside(0.5 * (p[0] + p[1])) {
                out = Some(match out {
                    None => (p[0], p[1]),
                    Some((lo, _)) => (lo, p[1]),
                });
            }
        }
        out
    }

    /// The scalar emission toward p: intensity · map(u, v) inside the cone (r ≤ 1),
    /// 0 outside or behind a spot; intensity for a point light (its map is ignored).
    pub fn weight(&self, intensity: f64, map: &LightMapSampler, p: Vec3) -> f64 {
        match self.kind {
            LightKind::Point => intensity,
            LightKind::Spot => match self.map_coords(p) {
                Some((u, v)) if map_r2(u, v) <= 1.0 => {
                    let m = map.eval(u, v);
                    if m == 0.0 {
                        0.0
                    } else {
                        intensity * m
                    }
                }
                _ => 0.0,
            },
        }
    }
}

/// Map coordinates (u, v) of p for a spot (see the module doc); `None` behind the light,
/// for an invalid spot and for a point light. Not clamped to [0, 1]².
pub fn spot_map_coords(light: &Light, p: Vec3) -> Option<(f64, f64)> {
    LightFrame::new(light).map_coords(p)
}

/// Scalar emission toward p (intensity · map, 0 outside the cone); see
/// [`LightFrame::weight`].
pub fn light_weight(light: &Light, map: &LightMapSampler, p: Vec3) -> f64 {
    LightFrame::new(light).weight(light.intensity, map, p)
}

/// I_l toward p: intensity · colour · map(u, v) inside the cone (r ≤ 1, every map
/// type), 0 outside it or behind the spot; intensity · colour for a point light.
pub fn light_radiance(light: &Light, map: &LightMapSampler, p: Vec3) -> [f64; 3] {
    let w = light_weight(light, map, p);
    light.color.map(|c| crate::scene::math::mul_no_nan(w, c))
}

/// Rasterise a light map into `size × size` unorm texels of `bits` bits (row-major,
/// row 0 at v = 0): texel (i, j) holds round-half-even(value · (2^bits − 1)) of the map
/// at its centre ((i + ½)/size, (j + ½)/size), and 0 where that centre lies outside
/// the cone's disc (r > 1) — so the texture carries the cone mask for every map type.
/// The outermost ring of texels is 0 too: the sampler clamps to the edge, so outside
/// the light's square frustum it repeats the edge texels, and the middles of the edges
/// lie inside the disc (r ≥ 1 − 1/size there); a non-zero edge would leak the map's rim
/// value to every direction beyond the frustum (a uniform spot would light all of it).
/// Errors: `light_map.size` (1 ..= 8192), `light_map.bits` (1 ..= 32), and the map's
/// own fields under `light_map.` (wrap with [`ConfigError::within`] for the light).
pub fn rasterize_lightmap(map: &LightMap, size: u32, bits: u32) -> Result<Vec<u32>, ConfigError> {
    let sampler = LightMapSampler::new(Some(map), "light_map")?;
    rasterize_sampler(&sampler, size, bits)
}

/// [`rasterize_lightmap`] for an already loaded sampler (`Uniform` gives the bare disc).
pub fn rasterize_sampler(
    map: &LightMapSampler,
    size: u32,
    bits: u32,
) -> Result<Vec<u32>, ConfigError> {
    rtl_model::error::check_range("light_map.size", size as u64, 1, 8192)?;
    rtl_model::error::check_range("light_map.bits", bits as u64, 1, 32)?;
    let max = ((1u64 << bits) - 1) as f64;
    let n = size as usize;
    let mut out = Vec::with_capacity(n * n);
    for j in 0..n {
        let v = (j as f64 + 0.5) / size as f64;
        for i in 0..n {
            let u = (i as f64 + 0.5) / size as f64;
            let border = i == 0 || j == 0 || i + 1 == n || j + 1 == n;
            let val = if !border && map_r2(u, v) <= 1.0 {
                map.eval(u, v).clamp(0.0, 1.0)
            } else {
                0.0
            };
            out.push((val * max).round_ties_even() as u32);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot() -> Light {
        Light {
            kind: LightKind::Spot,
            position: [0.0, 5.0, 0.0],
            direction: [0.0, -1.0, 0.0],
            cutoff_deg: 45.0,
            intensity: 2.0,
            color: [1.0, 0.5, 0.0],
            light_map: None,
        }
    }

    #[test]
    fn axis_maps_to_centre_and_edge_to_disc() {
        let l = spot();
        let (u, v) = spot_map_coords(&l, v3(0.0, 0.0, 0.0)).unwrap();
        assert!((u - 0.5).abs() < 1e-15 && (v - 0.5).abs() < 1e-15);
        // 45°: at depth 5 the cone radius is 5.
        let (u, v) = spot_map_coords(&l, v3(0.0, 0.0, 5.0)).unwrap();
        assert!((map_r2(u, v) - 1.0).abs() < 1e-12);
        assert!(spot_map_coords(&l, v3(0.0, 6.0, 0.0)).is_none());
        let r = light_radiance(&l, &LightMapSampler::Uniform, v3(0.0, 0.0, 0.0));
        assert_eq!(r, [2.0, 1.0, 0.0]);
        assert_eq!(
            light_radiance(&l, &LightMapSampler::Uniform, v3(6.0, 0.0, 0.0)),
            [0.0; 3]
        );
    }

    #[test]
    fn frame_matches_look_at() {
        use crate::scene::math::Mat4;
        let mut l = spot();
        l.direction = [0.3, -1.0, 0.2];
        l.cutoff_deg = 30.0;
        let f = LightFrame::new(&l);
        let pos = f.position;
        let m = Mat4::perspective(60.0, 1.0, 0.5, 50.0).mul(&Mat4::look_at(
            pos,
            pos + f.forward,
            v3(0.0, 1.0, 0.0),
        ));
        let p = v3(0.7, 1.0, -0.4);
        let c = m.apply(p);
        let (u, v) = f.map_coords(p).unwrap();
        assert!((u - (c[0] + c[3]) * 0.5 / c[3]).abs() < 1e-12);
        assert!((v - (c[3] - c[1]) * 0.5 / c[3]).abs() < 1e-12);
    }

    #[test]
    fn polka_and_rasterise() {
        let m = LightMap::PolkaDots {
            dots: 5,
            radius: 0.3,
        };
        let s = LightMapSampler::new(Some(&m), "x").unwrap();
        assert_eq!(s.eval(0.5, 0.5), 1.0);
        assert_eq!(s.eval(0.6, 0.5), 0.0); // cell edge, outside the dot
        let t = rasterize_lightmap(&m, 20, 8).unwrap();
        // Texel (10, 10) centre (0.525, 0.525): inside the centre dot, r² = 0.005.
        assert_eq!(t[210], 254);
        // Texel (9, 9) centre (0.475, 0.475) likewise; (11, 11) at 0.575 is outside.
        assert_eq!(t[9 * 20 + 9], 254);
        assert_eq!(t[11 * 20 + 11], 0);
        assert_eq!(t[0], 0);
        let e = rasterize_lightmap(&m, 0, 8).unwrap_err();
        assert_eq!(e.field(), "light_map.size");
        let e = LightMapSampler::new(
            Some(&LightMap::PolkaDots {
                dots: 5,
                radius: 0.7,
            }),
            "lights[1].light_map",
        )
        .unwrap_err();
        assert_eq!(e.field(), "lights[1].light_map.radius");
    }
}
