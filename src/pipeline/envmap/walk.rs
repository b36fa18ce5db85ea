//! The envmap renderer's raster walk and depth test: every triangle of the object is
//! set up and walked by the ONE `polygon_interpolator` (`pipeline::raster`), and the
//! nearest fragment per pixel wins an integer compare of the interpolated window-depth
//! codes (standing for the depth buffer). See [`super::render`]'s module notes, steps
//! 1–3.

use rtl_model::error::ConfigError;
use rtl_model::units::polygon_interpolator::PolygonInterpolator;
use rtl_model::Counters;

use super::roughness::TexGen;
use crate::pipeline::raster::{draw_triangle, host_attrs, Fragment, HostVertex};
use crate::scene::camera::CameraView;
use crate::scene::teapot::Triangle;

/// What the walk leaves for shading: per pixel the visible fragment and its (u, v)
/// codes (the render's attributes 8, 9, the measurement walk's, or zeros).
pub(super) struct Walk {
    pub frag_at: Vec<Option<(Fragment, [i64; 2])>>,
    pub triangles: usize,
    /// Fragments the interpolator produced, before the depth test.
    pub fragments: u64,
    /// The interpolator's counters (the measurement walk's are not counted).
    pub counters: Counters,
}

/// Walk `geo` (triangles with per-vertex λ) at `w` × `h` through `interp`. Each vertex
/// carries n (flipped for triangles seen from their back), e = eye − p, λ, the window
/// depth and the texgen (u, v). With `uv_probe` (per-vertex λ with the intended-λ
/// truth) a second, uncounted walk of the 10-attribute interpolator gives the (u, v)
/// codes; it must cover the same pixels, else an error naming
/// "envmap_render.texcoord". `uv_from_render`: (u, v) are the render's own attributes
/// 8 and 9 (the roughness-texture path).
#[allow(clippy::too_many_arguments)]
pub(super) fn walk(
    geo: &[(Triangle, [f64; 3])],
    cam: &CameraView,
    texgen: &TexGen,
    interp: &PolygonInterpolator,
    uv_probe: Option<&PolygonInterpolator>,
    uv_from_render: bool,
    w: u32,
    h: u32,
) -> Result<Walk, ConfigError> {
    let mut c_int = Counters::default();
    let n_px = w as usize * h as usize;
    let mut zbuf: Vec<i64> = vec![i64::MAX; n_px];
    let mut frag_at: Vec<Option<(Fragment, [i64; 2])>> = vec![None; n_px];
    let mut triangles = 0;
    let mut fragments = 0u64;
    for (tri, lam) in geo {
        let mut hv = [HostVertex {
            x: 0.0,
            y: 0.0,
            attrs: host_attrs([]),
        }; 3];
        let mut ok = true;
        // Two-sided lighting (GL's LIGHT_MODEL_TWO_SIDE): a triangle seen from its back
        // (the teapot is an open sheet: the inside of the rim and spout shows) gets its
        // normals flipped. Per primitive, host side (the facing is the sign of the
        // screen-space area the setup computes anyway).
        let face = (tri.p[1] - tri.p[0]).cross(tri.p[2] - tri.p[0]);
        let flip = if face.dot(cam.eye - tri.p[0]) < 0.0 {
            -1.0
        } else {
            1.0
        };
        for k in 0..3 {
            let Some((sx, sy, sz)) = cam.project(tri.p[k]) else {
                ok = false;
                break;
            };
            let n = tri.n[k] * flip;
            let e = cam.eye - tri.p[k];
            let (u, v) = texgen.uv(tri.p[k]);
            // An 8-attribute interpolator reads the first 8 (u, v unused).
            hv[k] = HostVertex {
                x: sx,
                y: sy,
                attrs: host_attrs([n.x, n.y, n.z, e.x, e.y, e.z, lam[k], sz, u, v]),
            };
        }
        if !ok {
            continue;
        }
        triangles += 1;
        let frags = draw_triangle(interp, &hv, w, h, &mut c_int)?;
        let probe = match uv_probe {
            Some(p) => {
                let f = draw_triangle(p, &hv, w, h, &mut Counters::default())?;
                if f.len() != frags.len()
                    || f.iter().zip(&frags).any(|(a, b)| (a.x, a.y) != (b.x, b.y))
                {
                    return Err(ConfigError::invalid(
                        "envmap_render.texcoord",
                        "the (u, v) measurement walk covered other pixels than the render",
                    ));
                }
                f
            }
            None => Vec::new(),
        };
        for (i, f) in frags.into_iter().enumerate() {
            fragments += 1;
            let k = (f.y * w + f.x) as usize;
            // Integer depth compare on the s16.16 window-depth code (less wins).
            if f.attrs[7] < zbuf[k] {
                zbuf[k] = f.attrs[7];
                let uv = match (uv_from_render, probe.get(i)) {
                    (true, _) => [f.attrs[8], f.attrs[9]],
                    (false, Some(g)) => [g.attrs[8], g.attrs[9]],
                    (false, None) => [0; 2],
                };
                frag_at[k] = Some((f, uv));
            }
        }
    }

    Ok(Walk {
        frag_at,
        triangles,
        fragments,
        counters: c_int,
    })
}
