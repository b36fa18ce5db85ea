//! Whole-image f64 reference of the built-in test scene: per pixel, the camera ray
//! meets the floor; the checker and light map are filtered ideally (exact weights on
//! the same texels), the Lambert term is evaluated at the pixel (not per vertex), and
//! the shadow is an exact ray test against the occluder's rectangles (no shadow map).

use crate::reference::texture_sampler::{Address, Filter, TextureRef};
use crate::scene::math::{v3, Vec3};
use crate::scene::test_scene::{
    checker_texels, lightmap_texels, occluder_quads, views, AMBIENT, CHECKER_REPEAT, CHECKER_SIZE,
    FLOOR_HALF, HEIGHT, LAMBERT_SCALE, LIGHTMAP_SIZE, LIGHT_RGB, WIDTH,
};

/// The reference image: RGB in 8-bit levels (0 ..= 255, unrounded) per pixel, `None`
/// where the floor does not cover the pixel centre.
pub fn render_reference() -> Vec<Option<[f64; 3]>> {
    let v = views();
    let inv = v.cam.inverse().expect("the camera matrix is invertible");
    let checker = TextureRef::from_codes(
        2,
        [CHECKER_SIZE as usize, CHECKER_SIZE as usize, 1],
        4,
        &checker_texels(),
        Filter::Linear,
        [Address::Wrap; 3],
    );
    let lightmap = TextureRef::from_codes(
        2,
        [LIGHTMAP_SIZE as usize, LIGHTMAP_SIZE as usize, 1],
        1,
        &lightmap_texels(),
        Filter::Linear,
        [Address::Clamp; 3],
    );
    let occluders = occluder_quads();
    let mut out = Vec::with_capacity((WIDTH * HEIGHT) as usize);
    for py in 0..HEIGHT {
        for px in 0..WIDTH {
            let nx = (px as f64 + 0.5) / WIDTH as f64 * 2.0 - 1.0;
            let ny = 1.0 - (py as f64 + 0.5) / HEIGHT as f64 * 2.0;
            let unproject = |z: f64| {
                let c = inv.apply(v3(nx, ny, z));
                v3(c[0] / c[3], c[1] / c[3], c[2] / c[3])
            };
            let (a, b) = (unproject(-1.0), unproject(1.0));
            let d = b - a;
            if d.y.abs() < 1e-12 {
                out.push(None);
                continue;
            }
            let t = -a.y / d.y;
            let p = a + d * t;
            if t < 0.0 || p.x.abs() > FLOOR_HALF || p.z.abs() > FLOOR_HALF {
                out.push(None);
                continue;
            }
            let tex = |k: f64| {
                (k + FLOOR_HALF) / (2.0 * FLOOR_HALF) * CHECKER_REPEAT * CHECKER_SIZE as f64
            };
            let albedo = checker.sample([tex(p.x), tex(p.z), 0.0]);
            let l = v.light.apply(p);
            let (s, tt) = ((l[0] + l[3]) * 0.5 / l[3], (l[3] - l[1]) * 0.5 / l[3]);
            let spot = if l[3] > 0.0 {
                lightmap.sample([s * LIGHTMAP_SIZE as f64, tt * LIGHTMAP_SIZE as f64, 0.0])[0]
                    / 255.0
            } else {
                0.0
            };
            let to_light = v.light_pos - p;
            let lambert =
                (to_light.normalized().y * LAMBERT_SCALE / to_light.dot(to_light)).clamp(0.0, 1.0);
            let lit = !occluders
                .iter()
                .any(|q| segment_hits_rect(p, v.light_pos, q));
            let light = if lit { spot * lambert } else { 0.0 };
            let rgb: [f64; 3] = std::array::from_fn(|c| {
                let amb = albedo[c] * AMBIENT as f64 / 255.0;
                let spot = albedo[c] * light * LIGHT_RGB[c] as f64 / 255.0;
                (amb + spot).min(255.0)
            });
            out.push(Some(rgb));
        }
    }
    out
}

/// Does the segment p → q cross the planar convex quad `r` (given in order)?
fn segment_hits_rect(p: Vec3, q: Vec3, r: &[Vec3; 4]) -> bool {
    let n = (r[1] - r[0]).cross(r[3] - r[0]);
    let (dp, dq) = ((p - r[0]).dot(n), (q - r[0]).dot(n));
    if dp * dq > 0.0 || dp == dq {
        return false;
    }
    let x = p + (q - p) * (dp / (dp - dq));
    (0..4).all(|i| {
        let (a, b) = (r[i], r[(i + 1) % 4]);
        (b - a).cross(x - a).dot(n) >= 0.0
    })
}
